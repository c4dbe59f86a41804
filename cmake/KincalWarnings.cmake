# Warnings as errors on our own code only; third-party headers come in as SYSTEM
# through their imported targets.
function(kincal_enable_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic -Werror)
endfunction()
