# cpack -G DEB (in the build directory) makes two Debian packages:
#   kincal         the program (bin/kincal); its Depends come from dpkg-shlibdeps, so they
#                  name the Debian runtime packages it loads (libceres3, libboost-program-
#                  options1.74.0, libipopt..., as built);
#   libkincal-dev  headers, static libraries, the CMake package and kincal.pc; it Depends on
#                  the -dev packages find_package(kincal) and pkg-config need;
#   python3-kincal the Python module (KINCAL_BUILD_PYTHON), in /usr/lib/python3/dist-packages.
# Installed under /usr. docs/library.md says how to build and install them.

set(CPACK_PACKAGE_NAME kincal)
set(CPACK_PACKAGE_VENDOR "kincal")
set(CPACK_PACKAGE_CONTACT "kincal developers <kincal@localhost>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "kinematic calibration of mechanisms from sensor readings")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)

set(CPACK_COMPONENTS_ALL development)
if(KINCAL_BUILD_CLI)
  list(PREPEND CPACK_COMPONENTS_ALL runtime)
endif()

set(CPACK_DEBIAN_RUNTIME_PACKAGE_NAME kincal)
set(CPACK_DEBIAN_RUNTIME_PACKAGE_SHLIBDEPS ON)
set(CPACK_COMPONENT_RUNTIME_DESCRIPTION
    "kincal: kinematic calibration from the command line\n"
    "Simulates calibrations, calibrates a mechanism model from measurement files, reports\n"
    "uncertainty and identifiability; solver backends gn, lm, Ceres, NLopt, Ipopt.")

# urdfdom (with TinyXML): the library reads and writes URDF (models/urdf_io.hpp); yaml-cpp:
# project files (framework/io/project_file.hpp).
set(KINCAL_DEV_DEPENDS libeigen3-dev nlohmann-json3-dev liburdfdom-dev libyaml-cpp-dev pkg-config)
if(KINCAL_WITH_CERES)
  list(APPEND KINCAL_DEV_DEPENDS libceres-dev)
endif()
if(KINCAL_WITH_NLOPT)
  list(APPEND KINCAL_DEV_DEPENDS libnlopt-cxx-dev)
endif()
if(KINCAL_WITH_IPOPT)
  list(APPEND KINCAL_DEV_DEPENDS coinor-libipopt-dev)
endif()
if(KINCAL_BUILD_CLI)
  list(APPEND KINCAL_DEV_DEPENDS libboost-program-options-dev)
endif()
if(TARGET kincal_vision)  # kincal::vision (kincal detect) links OpenCV
  list(APPEND KINCAL_DEV_DEPENDS libopencv-dev libopencv-contrib-dev)
endif()
list(JOIN KINCAL_DEV_DEPENDS ", " KINCAL_DEV_DEPENDS)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_NAME libkincal-dev)
set(CPACK_DEBIAN_DEVELOPMENT_PACKAGE_DEPENDS "${KINCAL_DEV_DEPENDS}")
set(CPACK_COMPONENT_DEVELOPMENT_DESCRIPTION
    "kincal: kinematic calibration library (development files)\n"
    "Headers <kincal/...>, the static libraries kincal and kincal_cli, the CMake package\n"
    "(find_package(kincal)) and kincal.pc.")

if(KINCAL_BUILD_PYTHON)
  list(APPEND CPACK_COMPONENTS_ALL python)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_NAME python3-kincal)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SHLIBDEPS ON)
  set(CPACK_DEBIAN_PYTHON_PACKAGE_DEPENDS "python3, python3-numpy")
  set(CPACK_DEBIAN_PYTHON_PACKAGE_SUGGESTS "python3-distributed, python3-matplotlib")
  set(CPACK_COMPONENT_PYTHON_DESCRIPTION
      "kincal: kinematic calibration from Python\n"
      "import kincal: models, kinematics, measurements, calibrations and studies on Dask.")
endif()

include(CPack)
