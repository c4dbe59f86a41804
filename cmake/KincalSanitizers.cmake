# Sanitizer and fuzzing builds (docs/reliability.md).
#
# KINCAL_SANITIZE: a comma-separated list for -fsanitize= (e.g. "address,undefined"), applied
# to everything this project compiles and links: the library, the CLI, the tests. Any
# undefined-behaviour report stops the program (-fno-sanitize-recover), so a test that
# triggers one fails. Third-party libraries (Ceres, Ipopt, ...) come prebuilt and are not
# instrumented.
#
# KINCAL_NO_SANITIZE: a comma-separated list for -fno-sanitize=, the checks of those groups
# left out. scripts/sanitize.sh's clang stage (CI's) leaves out UndefinedBehaviorSanitizer's
# pointer checks (null, alignment, object-size, pointer-overflow): they instrument every Eigen
# coefficient access and keep fixed-size kernels from being inlined, about 50 times slower
# (docs/reliability.md), while AddressSanitizer catches the out-of-bounds accesses and null
# dereferences they would; the gcc stage keeps the whole group.
#
# KINCAL_BUILD_FUZZERS: the libFuzzer targets in fuzz/ (clang only). Every object is also
# compiled with -fsanitize=fuzzer-no-link, so that the fuzzers see coverage of the library
# code; the same build still runs the test suite.

set(KINCAL_SANITIZE "" CACHE STRING
    "Sanitizers for -fsanitize= (e.g. address,undefined); empty for none")
set(KINCAL_NO_SANITIZE "" CACHE STRING
    "Checks for -fno-sanitize= (e.g. null,alignment); empty to keep every check")
option(KINCAL_BUILD_FUZZERS "Build the libFuzzer targets in fuzz/ (clang only)" OFF)

if(KINCAL_SANITIZE)
  message(STATUS "Sanitizers: ${KINCAL_SANITIZE} (${CMAKE_CXX_COMPILER_ID})")
  add_compile_options(-fsanitize=${KINCAL_SANITIZE} -fno-sanitize-recover=all
                      -fno-omit-frame-pointer)
  add_link_options(-fsanitize=${KINCAL_SANITIZE} -fno-sanitize-recover=all)
  if(KINCAL_NO_SANITIZE)
    message(STATUS "Sanitizer checks left out: ${KINCAL_NO_SANITIZE}")
    add_compile_options(-fno-sanitize=${KINCAL_NO_SANITIZE})
    add_link_options(-fno-sanitize=${KINCAL_NO_SANITIZE})
  endif()
  # g++ 12 under -fsanitize=address reports -Wmaybe-uninitialized on copies and assignments of
  # a disengaged std::optional<VectorXd> (SolverOptions::lower_bounds, in
  # conformance_test.cpp and ipopt_solver_test.cpp): the instrumentation hides that the
  # payload is only read when engaged. The warning stays an error in the normal build, which
  # compiles the same code without instrumentation.
  if(CMAKE_CXX_COMPILER_ID STREQUAL "GNU")
    add_compile_options(-Wno-maybe-uninitialized)
  endif()
endif()

if(KINCAL_BUILD_FUZZERS)
  if(NOT CMAKE_CXX_COMPILER_ID MATCHES "Clang")
    message(FATAL_ERROR "KINCAL_BUILD_FUZZERS needs clang (libFuzzer): configure with "
                        "-DCMAKE_CXX_COMPILER=clang++-14")
  endif()
  add_compile_options(-fsanitize=fuzzer-no-link)
endif()
