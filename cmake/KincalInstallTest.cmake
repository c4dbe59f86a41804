# The installed package, tested as a user would use it (tests/install/installed_package.sh):
#   installed_package_install            cmake --install of this build to a scratch prefix
#   installed_package_cmake_example      examples/custom_model/ configured with only
#                                        find_package(kincal) against that prefix, built, run
#                                        (its CLI calibrates the example arm from files)
#   installed_package_pkg_config_example the complete example of docs/library.md, compiled
#                                        with pkg-config's flags only, and run
#   installed_package_workflow_example   its calibrate-workflow example, the same way
#   installed_package_plugin             examples/plugin/ built with kincal_add_plugin
#                                        against that prefix, used by the installed kincal
#                                        (--plugin, KINCAL_PLUGIN_PATH): list, simulate,
#                                        calibrate, observability, design, export, check
# kincal itself is not rebuilt: the prefix is this build's install. The example's build
# directory stays under the build tree (and goes through ccache when this build does), so
# a second run only relinks.

set(KINCAL_INSTALL_TEST_DIR "${kincal_BINARY_DIR}/installed-package-test")
set(KINCAL_INSTALL_TEST_SCRIPT "${kincal_SOURCE_DIR}/tests/install/installed_package.sh")

set(why_not "")
if(NOT KINCAL_INSTALL)
  set(why_not "configured with KINCAL_INSTALL=OFF (no install rules)")
elseif(NOT KINCAL_BUILD_CLI)
  set(why_not "configured with KINCAL_BUILD_CLI=OFF (the example uses the cli component)")
elseif(KINCAL_SANITIZE)
  set(why_not "sanitizer build (${KINCAL_SANITIZE}): the installed targets do not carry "
              "-fsanitize to the example's link")
endif()

if(why_not)
  add_test(NAME installed_package_not_tested
           COMMAND sh -c "echo 'skipped: ${why_not}'; exit 77")
  set_tests_properties(installed_package_not_tested PROPERTIES SKIP_RETURN_CODE 77)
  return()
endif()

set(common_args "${KINCAL_INSTALL_TEST_DIR}" "${kincal_SOURCE_DIR}" "${kincal_BINARY_DIR}")
add_test(NAME installed_package_install
         COMMAND bash "${KINCAL_INSTALL_TEST_SCRIPT}" install ${common_args})
add_test(NAME installed_package_cmake_example
         COMMAND bash "${KINCAL_INSTALL_TEST_SCRIPT}" cmake ${common_args})
add_test(NAME installed_package_pkg_config_example
         COMMAND bash "${KINCAL_INSTALL_TEST_SCRIPT}" pkg-config ${common_args})
add_test(NAME installed_package_workflow_example
         COMMAND bash "${KINCAL_INSTALL_TEST_SCRIPT}" workflow ${common_args})
add_test(NAME installed_package_plugin
         COMMAND bash "${KINCAL_INSTALL_TEST_SCRIPT}" plugin ${common_args})
set_tests_properties(installed_package_install PROPERTIES FIXTURES_SETUP kincal_installed
                                                          TIMEOUT 120)
set_tests_properties(installed_package_cmake_example installed_package_pkg_config_example
                     installed_package_workflow_example installed_package_plugin
                     PROPERTIES FIXTURES_REQUIRED kincal_installed TIMEOUT 600)
set_tests_properties(
  installed_package_install installed_package_cmake_example installed_package_pkg_config_example
  installed_package_workflow_example installed_package_plugin PROPERTIES ENVIRONMENT
             "CMAKE_COMMAND=${CMAKE_COMMAND};CXX=${CMAKE_CXX_COMPILER};CMAKE_GENERATOR=${CMAKE_GENERATOR};KINCAL_LAUNCHER=${CMAKE_CXX_COMPILER_LAUNCHER};KINCAL_BUILD_TYPE=${CMAKE_BUILD_TYPE}")
