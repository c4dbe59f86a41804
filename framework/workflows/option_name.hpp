#pragma once
// An option as a face spells it in a workflow's messages: the program's "--prior-std"
// (prefix "--") or Python's "prior_std" (prefix "": dashes become underscores).

#include <string>

namespace kincal {

inline std::string option_name(const std::string& prefix, std::string name) {
  if (prefix.empty())
    for (char& c : name)
      if (c == '-') c = '_';
  return prefix + name;
}

}  // namespace kincal
