# Warnings on our own code only; third-party headers come in as SYSTEM through their imported
# targets. Always PRIVATE, so nothing reaches a project that links kincal; as errors only
# with KINCAL_WARNINGS_AS_ERRORS (ON by default when kincal is the top-level project), so
# that a newer compiler's new warning cannot break a project that merely builds kincal.
function(kincal_enable_warnings target)
  target_compile_options(${target} PRIVATE -Wall -Wextra -Wpedantic)
  if(KINCAL_WARNINGS_AS_ERRORS)
    target_compile_options(${target} PRIVATE -Werror)
  endif()
endfunction()
