#pragma once
// A backend's own settings as a typed struct with defaults (LevenbergMarquardtSettings in
// solvers/levenberg_marquardt.hpp, CeresSettings, ...), filled in code or parsed once from
// key=value text at the edge (the command line's --solver-option, Python's solver_options) by
// Solver::parse_settings, checked as a whole by validity_error(), and listed with every value
// in force, defaults included, by in_force() for the reports.
//
// A settings struct lists its fields once (key, member, allowed words) and derives from
// TypedBackendSettings<itself>, which turns that list into set() and in_force(): the text a
// report shows is the text set() reads back to the same value.

#include <cmath>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>
#include <variant>
#include <vector>

namespace kincal {

/// Thrown for invalid solver names or options: bad input, reported before any work.
class InvalidSolverOptions : public std::invalid_argument {
 public:
  using std::invalid_argument::invalid_argument;
};

class BackendSettings {
 public:
  virtual ~BackendSettings() = default;
  /// Sets one setting from its text ("linear_solver", "qr"). Throws InvalidSolverOptions
  /// naming the key for an unknown key or a value of the wrong kind (not the solver: the
  /// caller, Solver::parse_settings, prefixes it).
  virtual void set(const std::string& key, const std::string& value) = 0;
  /// Every setting and its value as text that set() reads back, defaults included, in the
  /// order the backend declares them.
  virtual std::vector<std::pair<std::string, std::string>> in_force() const = 0;
  /// Empty when the settings are valid together, else what is wrong ("max_radius_growth must
  /// be > 1"). Checked by the backend's check_options, so settings filled in code are held to
  /// the rules text is.
  virtual std::string validity_error() const { return {}; }
  virtual std::unique_ptr<BackendSettings> clone() const = 0;
  /// Settings of the same type at their defaults.
  virtual std::unique_ptr<BackendSettings> defaults() const = 0;
};

/// The settings of a backend that takes none.
class NoBackendSettings final : public BackendSettings {
 public:
  void set(const std::string& key, const std::string& value) override;
  std::vector<std::pair<std::string, std::string>> in_force() const override { return {}; }
  std::unique_ptr<BackendSettings> clone() const override {
    return std::make_unique<NoBackendSettings>();
  }
  std::unique_ptr<BackendSettings> defaults() const override {
    return std::make_unique<NoBackendSettings>();
  }
};

namespace backend_settings {
/// Text to a value of one setting; throws InvalidSolverOptions "option KEY='TEXT' is not a
/// number" (an integer, one of: ...). `infinity_word`, when not empty, is read as +infinity.
double parse_double(const std::string& key, const std::string& text,
                    const std::string& infinity_word = {});
int parse_int(const std::string& key, const std::string& text);
std::string parse_choice(const std::string& key, const std::string& text,
                         const std::vector<std::string>& choices);
/// The shortest text that reads back to `value` ("1e-12", "0.75"); `infinity_word` for +inf.
std::string text_of(double value, const std::string& infinity_word = {});
/// "unknown option 'KEY' (known: a, b, c)".
[[noreturn]] void unknown_key(const std::string& key, const std::vector<std::string>& known);
}  // namespace backend_settings

/// One field of a settings struct S: its key, its member, and for text fields the words it
/// may take (any text when empty); booleans read "true" and "false".
template <class S>
struct SettingField {
  std::string key;
  std::variant<double S::*, int S::*, bool S::*, std::string S::*> member;
  std::vector<std::string> choices = {};
  std::string infinity_word = {};  ///< a double that may be +infinity, written so ("none")
};

/// set() and in_force() of a settings struct S that declares
/// `static const std::vector<SettingField<S>>& fields();`.
template <class S>
class TypedBackendSettings : public BackendSettings {
 public:
  void set(const std::string& key, const std::string& value) override {
    S& self = static_cast<S&>(*this);
    for (const SettingField<S>& field : S::fields()) {
      if (field.key != key) continue;
      std::visit(
          [&](auto member) {
            using T = std::decay_t<decltype(self.*member)>;
            if constexpr (std::is_same_v<T, double>)
              self.*member = backend_settings::parse_double(key, value, field.infinity_word);
            else if constexpr (std::is_same_v<T, int>)
              self.*member = backend_settings::parse_int(key, value);
            else if constexpr (std::is_same_v<T, bool>)
              self.*member =
                  backend_settings::parse_choice(key, value, {"true", "false"}) == "true";
            else
              self.*member = field.choices.empty()
                                 ? value
                                 : backend_settings::parse_choice(key, value, field.choices);
          },
          field.member);
      return;
    }
    std::vector<std::string> known;
    for (const SettingField<S>& field : S::fields()) known.push_back(field.key);
    backend_settings::unknown_key(key, known);
  }

  std::vector<std::pair<std::string, std::string>> in_force() const override {
    const S& self = static_cast<const S&>(*this);
    std::vector<std::pair<std::string, std::string>> out;
    for (const SettingField<S>& field : S::fields())
      out.emplace_back(field.key, std::visit(
                                      [&](auto member) -> std::string {
                                        using T = std::decay_t<decltype(self.*member)>;
                                        if constexpr (std::is_same_v<T, double>)
                                          return backend_settings::text_of(self.*member,
                                                                           field.infinity_word);
                                        else if constexpr (std::is_same_v<T, int>)
                                          return std::to_string(self.*member);
                                        else if constexpr (std::is_same_v<T, bool>)
                                          return self.*member ? "true" : "false";
                                        else
                                          return self.*member;
                                      },
                                      field.member));
    return out;
  }

  std::unique_ptr<BackendSettings> clone() const override {
    return std::make_unique<S>(static_cast<const S&>(*this));
  }
  std::unique_ptr<BackendSettings> defaults() const override { return std::make_unique<S>(); }
};

}  // namespace kincal
