# SPDX-License-Identifier: BSD-3-Clause
# Installation as a CMake package (find_package(emslam)) with the shipped
# configurations and data, and a Debian package (cpack -G DEB).
include(CMakePackageConfigHelpers)

set(EMSLAM_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/emslam)
set(EMSLAM_INSTALL_CONFIGDIR ${CMAKE_INSTALL_DATADIR}/emslam/config)

install(EXPORT emslamTargets NAMESPACE emslam:: DESTINATION ${EMSLAM_INSTALL_CMAKEDIR})
configure_package_config_file(${CMAKE_CURRENT_LIST_DIR}/emslamConfig.cmake.in
    ${PROJECT_BINARY_DIR}/emslamConfig.cmake
    INSTALL_DESTINATION ${EMSLAM_INSTALL_CMAKEDIR}
    PATH_VARS EMSLAM_INSTALL_CONFIGDIR)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/emslamConfigVersion.cmake
    COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/emslamConfig.cmake
    ${PROJECT_BINARY_DIR}/emslamConfigVersion.cmake DESTINATION ${EMSLAM_INSTALL_CMAKEDIR})

# The INI files every app takes, and the data they refer to.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/config/ DESTINATION ${EMSLAM_INSTALL_CONFIGDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/share/emslam/ DESTINATION ${CMAKE_INSTALL_DATADIR}/emslam)

set(CPACK_PACKAGE_NAME emslam)
set(CPACK_PACKAGE_VENDOR "emslam")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Entropy Minimization SLAM (Saez & Escolano) for MRPT: stereo egomotion and entropy-based global rectification")
set(CPACK_PACKAGE_CONTACT "emslam developers")
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "emslam developers")
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)  # Depends: from the linked system libraries
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
include(CPack)
