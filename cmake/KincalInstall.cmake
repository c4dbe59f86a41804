# Install rules, the CMake package (find_package(kincal)), kincal.pc and the Debian package
# (cpack -G DEB). Included by the top-level CMakeLists.txt when KINCAL_INSTALL is ON.
# docs/library.md is the user's side of this file; docs/architecture.md says why it is so.

include(CMakePackageConfigHelpers)

set(KINCAL_INSTALL_CMAKEDIR "${CMAKE_INSTALL_LIBDIR}/cmake/kincal")

# ---- the library and its headers -------------------------------------------
# Headers are installed as the build tree includes them: <kincal/<folder>/x.hpp>, plus the
# generated <kincal/version.hpp>. Of cli/ only run.hpp is public (the rest is the commands'
# internals, and includes Boost); the pages for people are the library's (framework/report/).
install(TARGETS kincal EXPORT kincalTargets
        ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT development)
foreach(folder IN LISTS KINCAL_HEADER_FOLDERS)
  if(folder STREQUAL "cli" OR (folder STREQUAL "vision" AND NOT TARGET kincal_vision))
    continue()
  endif()
  install(DIRECTORY "${PROJECT_SOURCE_DIR}/${folder}/"
          DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/kincal/${folder}" COMPONENT development
          FILES_MATCHING PATTERN "*.hpp")
endforeach()
install(FILES "${KINCAL_BUILD_INCLUDE_DIR}/kincal/version.hpp"
        DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/kincal" COMPONENT development)
install(EXPORT kincalTargets NAMESPACE kincal:: DESTINATION "${KINCAL_INSTALL_CMAKEDIR}"
        COMPONENT development)

# ---- the CLI: kincal::cli (library) and kincal::kincal-cli (the program) ----
if(KINCAL_BUILD_CLI)
  set_target_properties(kincal_cli PROPERTIES EXPORT_NAME cli)
  install(TARGETS kincal-cli EXPORT kincalCliTargets
          RUNTIME DESTINATION "${CMAKE_INSTALL_BINDIR}" COMPONENT runtime)
  install(TARGETS kincal_cli EXPORT kincalCliTargets
          ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT development)
  if(TARGET kincal_vision)
    set_target_properties(kincal_vision PROPERTIES EXPORT_NAME vision)
    install(TARGETS kincal_vision EXPORT kincalCliTargets
            ARCHIVE DESTINATION "${CMAKE_INSTALL_LIBDIR}" COMPONENT development)
  endif()
  install(FILES "${PROJECT_SOURCE_DIR}/cli/run.hpp"
          DESTINATION "${CMAKE_INSTALL_INCLUDEDIR}/kincal/cli" COMPONENT development)
  install(EXPORT kincalCliTargets NAMESPACE kincal:: DESTINATION "${KINCAL_INSTALL_CMAKEDIR}"
          COMPONENT development)
endif()

# ---- kincalConfig.cmake, its version file ----------------------------------
set(KINCAL_ENABLED_BACKENDS "")
foreach(backend IN ITEMS ceres nlopt ipopt)
  string(TOUPPER "${backend}" upper)
  if(KINCAL_WITH_${upper})
    list(APPEND KINCAL_ENABLED_BACKENDS ${backend})
  endif()
endforeach()
foreach(option IN ITEMS KINCAL_WITH_CERES KINCAL_WITH_NLOPT KINCAL_WITH_IPOPT)
  if(${option})
    set(${option} ON)
  else()
    set(${option} OFF)
  endif()
endforeach()
if(TARGET kincal_vision)
  set(KINCAL_VISION_BUILT TRUE)
else()
  set(KINCAL_VISION_BUILT FALSE)
endif()
configure_package_config_file(cmake/kincalConfig.cmake.in
                              "${PROJECT_BINARY_DIR}/kincalConfig.cmake"
                              INSTALL_DESTINATION "${KINCAL_INSTALL_CMAKEDIR}")
# 0.x: a minor version may break the API, so only the same major.minor is compatible.
write_basic_package_version_file("${PROJECT_BINARY_DIR}/kincalConfigVersion.cmake"
                                 COMPATIBILITY SameMinorVersion)
install(FILES "${PROJECT_BINARY_DIR}/kincalConfig.cmake"
              "${PROJECT_BINARY_DIR}/kincalConfigVersion.cmake"
              "${PROJECT_SOURCE_DIR}/cmake/KincalPlugin.cmake"
        DESTINATION "${KINCAL_INSTALL_CMAKEDIR}" COMPONENT development)

# ---- kincal.pc ---------------------------------------------------------------
# Relocatable: the prefix is found from where the .pc file is (cmake --install --prefix P).
# kincal is a static library, so Libs and Requires carry what it links: NLopt, Ipopt, Eigen,
# nlohmann-json and urdfdom (with TinyXML) through their own .pc files; Ceres has none, and -lceres is enough where
# libceres is a shared library that brings its own dependencies (Debian's libceres.so; the
# CMake package links what Ceres' own CMake config says, on Debian the static libceres.a).
set(KINCAL_PC_DIR "${CMAKE_INSTALL_LIBDIR}/pkgconfig")
file(RELATIVE_PATH KINCAL_PC_TO_PREFIX "/prefix/${KINCAL_PC_DIR}" "/prefix")
string(REGEX REPLACE "/$" "" KINCAL_PC_TO_PREFIX "${KINCAL_PC_TO_PREFIX}")
set(KINCAL_PC_REQUIRES "eigen3 nlohmann_json urdfdom tinyxml yaml-cpp")
set(KINCAL_PC_CFLAGS "")
set(KINCAL_PC_LIBS "")
if(KINCAL_WITH_CERES)
  string(APPEND KINCAL_PC_CFLAGS " -DKINCAL_WITH_CERES=1")
  string(APPEND KINCAL_PC_LIBS " -lceres")
endif()
if(KINCAL_WITH_NLOPT)
  string(APPEND KINCAL_PC_CFLAGS " -DKINCAL_WITH_NLOPT=1")
  if(KINCAL_NLOPT_TARGET STREQUAL "NLopt::nlopt_cxx")
    string(APPEND KINCAL_PC_REQUIRES " nlopt_cxx")
  else()
    string(APPEND KINCAL_PC_REQUIRES " nlopt")
  endif()
endif()
if(KINCAL_WITH_IPOPT)
  string(APPEND KINCAL_PC_CFLAGS " -DKINCAL_WITH_IPOPT=1")
  string(APPEND KINCAL_PC_REQUIRES " ipopt")
endif()
string(APPEND KINCAL_PC_LIBS " -pthread")
string(STRIP "${KINCAL_PC_CFLAGS}" KINCAL_PC_CFLAGS)
configure_file(cmake/kincal.pc.in "${PROJECT_BINARY_DIR}/kincal.pc" @ONLY)
install(FILES "${PROJECT_BINARY_DIR}/kincal.pc" DESTINATION "${KINCAL_PC_DIR}"
        COMPONENT development)

# The Debian packages are kincal's own: a project that installs kincal with it packages itself.
if(PROJECT_IS_TOP_LEVEL)
  include(KincalPackage)
endif()
