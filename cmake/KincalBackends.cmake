# Optional solver backends, those that need a third-party library. Each one is a CMake
# option; when ON, kincal_add_optional_backends() compiles its source file into the library
# and a PUBLIC KINCAL_WITH_<NAME> definition tells solvers/builtin_solvers.cpp to register it
# (and the tests which backends to expect). When OFF it is registered as unavailable.
#
# The top-level CMakeLists.txt builds every other solvers/*.cpp: a backend without a
# third-party library needs no CMake edit. A new optional backend adds its source here and a
# block below.

set(KINCAL_OPTIONAL_SOLVER_SOURCES
    "${CMAKE_CURRENT_SOURCE_DIR}/solvers/ceres_solver.cpp"
    "${CMAKE_CURRENT_SOURCE_DIR}/solvers/nlopt_solver.cpp"
    "${CMAKE_CURRENT_SOURCE_DIR}/solvers/ipopt_solver.cpp")

# A macro, not a function: find_package results and imported targets stay visible to the
# rest of the project, as if this were written inline after add_library(kincal).
macro(kincal_add_optional_backends)
  if(KINCAL_WITH_CERES)
    find_package(Ceres REQUIRED)
    target_sources(kincal PRIVATE solvers/ceres_solver.cpp)
    target_link_libraries(kincal PRIVATE Ceres::ceres)
    target_compile_definitions(kincal PUBLIC KINCAL_WITH_CERES=1)
  endif()

  if(KINCAL_WITH_NLOPT)
    # Debian ships two configs that are both named NLoptConfig.cmake: cmake/nlopt (the C build,
    # target NLopt::nlopt) and cmake/nlopt_cxx (the build with the C++ algorithms StoGO and
    # AGS, target NLopt::nlopt_cxx). A plain find_package picks the C one; prefer the full one
    # so that every algorithm name works. nlopt.hpp itself is header-only over the C API, so
    # either target serves our code.
    find_path(KINCAL_NLOPT_CXX_CONFIG_DIR NLoptConfig.cmake
              PATHS ${CMAKE_PREFIX_PATH} ${CMAKE_SYSTEM_PREFIX_PATH}
              PATH_SUFFIXES lib/${CMAKE_LIBRARY_ARCHITECTURE}/cmake/nlopt_cxx lib64/cmake/nlopt_cxx
                            lib/cmake/nlopt_cxx
              NO_DEFAULT_PATH)
    find_package(NLopt REQUIRED CONFIG HINTS ${KINCAL_NLOPT_CXX_CONFIG_DIR})
    if(TARGET NLopt::nlopt_cxx)
      set(KINCAL_NLOPT_TARGET NLopt::nlopt_cxx)
    else()
      set(KINCAL_NLOPT_TARGET NLopt::nlopt)
    endif()
    message(STATUS "NLopt ${NLOPT_VERSION}: ${KINCAL_NLOPT_TARGET} from ${NLopt_DIR}")
    target_sources(kincal PRIVATE solvers/nlopt_solver.cpp)
    target_link_libraries(kincal PRIVATE ${KINCAL_NLOPT_TARGET})
    target_compile_definitions(kincal PUBLIC KINCAL_WITH_NLOPT=1)
  endif()

  if(KINCAL_WITH_IPOPT)
    find_package(PkgConfig REQUIRED)
    # The prefix is ours (target PkgConfig::KINCAL_IPOPT), so that kincalConfig.cmake can
    # recreate the same target in a consumer without clashing with the consumer's own.
    pkg_check_modules(KINCAL_IPOPT REQUIRED IMPORTED_TARGET ipopt)
    # Include directories of imported targets are SYSTEM, so Ipopt's headers (coin/...) do not
    # trip our -Werror. Debian's 3.11 has MUMPS built in; it loads the HSL solvers from
    # libhsl.so and Pardiso from libpardiso.so at run time, when they exist.
    message(STATUS "Ipopt ${KINCAL_IPOPT_VERSION} (pkg-config)")
    target_sources(kincal PRIVATE solvers/ipopt_solver.cpp)
    target_link_libraries(kincal PRIVATE PkgConfig::KINCAL_IPOPT)
    target_compile_definitions(kincal PUBLIC KINCAL_WITH_IPOPT=1)
  endif()
endmacro()
