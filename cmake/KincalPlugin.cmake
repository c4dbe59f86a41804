# kincal_add_plugin(TARGET SOURCES...): a kincal plug-in (framework/extension/plugin.hpp), a shared
# library that `kincal --plugin FILE`, KINCAL_PLUGIN_PATH or kincal::load_plugin() loads.
# One of SOURCES has the line KINCAL_PLUGIN(your_register_function).
#
# The plug-in links the parts of the static kincal library it uses and keeps them to
# itself: every symbol but the entry point is hidden (--exclude-libs, hidden visibility), so
# it never binds to, or overrides, the loading program's copy. Undefined symbols are an error
# at link time rather than when kincal loads the plug-in.
# Installed with the package (kincalConfig.cmake includes it) and used in kincal's own tree.
function(kincal_add_plugin target)
  if(NOT ARGN)
    message(FATAL_ERROR "kincal_add_plugin(${target}): no source files")
  endif()
  add_library(${target} MODULE ${ARGN})
  target_link_libraries(${target} PRIVATE kincal::kincal)
  set_target_properties(${target} PROPERTIES CXX_VISIBILITY_PRESET hidden
                                             VISIBILITY_INLINES_HIDDEN ON)
  if(CMAKE_SYSTEM_NAME STREQUAL "Linux")
    target_link_options(${target} PRIVATE "LINKER:--exclude-libs,ALL")
    # Sanitizer and coverage runtimes live in the loading program (clang links them into
    # executables only), so a plug-in built with them has undefined symbols by design.
    string(FIND "${CMAKE_CXX_FLAGS} ${CMAKE_SHARED_LINKER_FLAGS}" "-fsanitize" sanitized)
    if(NOT KINCAL_SANITIZE AND NOT KINCAL_BUILD_FUZZERS AND sanitized EQUAL -1)
      target_link_options(${target} PRIVATE "LINKER:--no-undefined")
    endif()
  endif()
endfunction()
