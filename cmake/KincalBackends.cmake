# Optional solver backends. Each one is a CMake option; when ON, its source file is
# compiled into the library and a KINCAL_WITH_<NAME> definition tells
# solvers/builtin_solvers.cpp to register it.

if(KINCAL_WITH_CERES)
  find_package(Ceres REQUIRED)
  target_sources(kincal PRIVATE solvers/ceres_solver.cpp)
  target_link_libraries(kincal PRIVATE Ceres::ceres)
  target_compile_definitions(kincal PUBLIC KINCAL_WITH_CERES=1)
endif()

if(KINCAL_WITH_NLOPT)
  find_package(NLopt REQUIRED)
  target_sources(kincal PRIVATE solvers/nlopt_solver.cpp)
  target_link_libraries(kincal PRIVATE NLopt::nlopt)
  target_compile_definitions(kincal PUBLIC KINCAL_WITH_NLOPT=1)
endif()

if(KINCAL_WITH_IPOPT)
  find_package(PkgConfig REQUIRED)
  pkg_check_modules(IPOPT REQUIRED IMPORTED_TARGET ipopt)
  target_sources(kincal PRIVATE solvers/ipopt_solver.cpp)
  target_link_libraries(kincal PRIVATE PkgConfig::IPOPT)
  target_compile_definitions(kincal PUBLIC KINCAL_WITH_IPOPT=1)
endif()
