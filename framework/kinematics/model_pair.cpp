#include "kincal/framework/kinematics/model_pair.hpp"

#include <stdexcept>
#include <vector>

#include "kincal/framework/base/message_excerpt.hpp"

namespace kincal {

namespace {

// The first difference between two lists of names, or "".
std::string first_difference(const std::vector<std::string>& a, const std::vector<std::string>& b,
                             const std::string& what, const std::string& a_label,
                             const std::string& b_label) {
  for (std::size_t i = 0; i < a.size() && i < b.size(); ++i)
    if (a[i] != b[i])
      return what + " " + std::to_string(i + 1) + " is '" + printable(a[i]) + "' in " + a_label +
             " and '" + printable(b[i]) + "' in " + b_label;
  if (a.size() != b.size())
    return std::to_string(a.size()) + " " + what + "s in " + a_label + ", " +
           std::to_string(b.size()) + " in " + b_label;
  return "";
}

}  // namespace

void check_same_parameters(const MeasurementModel& a, const std::string& a_label,
                           const MeasurementModel& b, const std::string& b_label) {
  std::string why = first_difference(a.parameters().names(), b.parameters().names(), "parameter",
                                     a_label, b_label);
  if (why.empty())
    for (int i = 0; i < a.parameters().size(); ++i)
      if (a.parameters()[i].unit != b.parameters()[i].unit) {
        why = "parameter " + printable(a.parameters()[i].name) + " is in " +
              a.parameters()[i].unit + " in " + a_label + " and in " + b.parameters()[i].unit +
              " in " + b_label;
        break;
      }
  if (why.empty())
    why = first_difference(a.mechanism().actuator_names(), b.mechanism().actuator_names(),
                           "actuator", a_label, b_label);
  if (why.empty())
    why = first_difference(a.reading_names(), b.reading_names(), "reading", a_label, b_label);
  if (!why.empty())
    throw std::invalid_argument(a_label + " and " + b_label + " do not have the same parameters: " +
                                why + "; expected two models of the same machine");
}

}  // namespace kincal
