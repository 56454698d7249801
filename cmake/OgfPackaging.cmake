# Installation layout beyond the programs, and the Debian package (CPack DEB) of the whole project.
# Included last from the top-level CMakeLists.txt, once every install() rule exists.
#
#   cmake --install build --prefix /tmp/x     bin/ogf-*, lib/systemd/system/*, etc/ogf/*.yaml,
#                                              lib/sysctl.d/, share/java/lcmtypes_ogf.jar, share/doc/ogf/
#   cd build && cpack                          ogf_<version>-1_<arch>.deb: the same under /usr, with the
#                                              configuration in /etc/ogf (conffiles) and units in
#                                              /lib/systemd/system (packaging/debian-layout.cmake)
#
# Depends is computed by dpkg-shlibdeps (package dpkg-dev) from the programs' shared libraries. The
# maintainer scripts (packaging/debian/) reload systemd but enable and start nothing.

# Documentation the units' Documentation= line points at (file:///usr/share/doc/ogf/README.md).
install(FILES "${PROJECT_SOURCE_DIR}/README.md" DESTINATION "${CMAKE_INSTALL_DOCDIR}")
install(DIRECTORY "${PROJECT_SOURCE_DIR}/docs/" DESTINATION "${CMAKE_INSTALL_DOCDIR}" FILES_MATCHING PATTERN "*.md")
install(FILES "${PROJECT_SOURCE_DIR}/packaging/debian/copyright" DESTINATION "${CMAKE_INSTALL_DOCDIR}")

set(OGF_PACKAGE_MAINTAINER "ogf maintainers <maintainers@users.noreply.h-seed-a49a0451.example>"
    CACHE STRING "Maintainer field of the Debian package")

set(CPACK_GENERATOR "DEB")
set(CPACK_SOURCE_GENERATOR "TGZ")
set(CPACK_PACKAGE_NAME "ogf")
set(CPACK_PACKAGE_VENDOR "ogf")
set(CPACK_PACKAGE_VERSION "${PROJECT_VERSION}")
set(CPACK_PACKAGE_CONTACT "${OGF_PACKAGE_MAINTAINER}")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGING_INSTALL_PREFIX "/usr")
set(CPACK_STRIP_FILES ON)
set(CPACK_PRE_BUILD_SCRIPTS "${PROJECT_SOURCE_DIR}/packaging/debian-layout.cmake")

set(CPACK_DEBIAN_PACKAGE_NAME "ogf")
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_MAINTAINER "${OGF_PACKAGE_MAINTAINER}")
set(CPACK_DEBIAN_PACKAGE_SECTION "science")
set(CPACK_DEBIAN_PACKAGE_PRIORITY "optional")
set(CPACK_DEBIAN_COMPRESSION_TYPE "xz")
# The synopsis is CPACK_PACKAGE_DESCRIPTION_SUMMARY; this is the extended part (lines under 80 columns).
set(CPACK_DEBIAN_PACKAGE_DESCRIPTION "ogf-driver reads a Velodyne VLP-16 (or HDL-32E, VLP-32C) over UDP or a
capture and publishes scans on LCM; ogf-mapper builds an occupancy map from
them with the Occupancy Grid Filter and keeps it across restarts. Both run
as hardened systemd services (ogf.target, not enabled on install). Also
ships the replay, simulation, decoding, map and evaluation tools,
lcmtypes_ogf.jar and ogf_spy.jar (its launcher) for lcm-spy, and the Python
package `ogf` (maps as numpy arrays, live map and 2-D grid clients).")
# Depends from the ELF programs' DT_NEEDED, through dpkg-shlibdeps and the shlibs of installed packages,
# after libjs-three: ogf-view serves its /usr/share/javascript/three/three.min.js.
set(CPACK_DEBIAN_PACKAGE_DEPENDS "libjs-three")
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# lcm-logger records the bus on the robot; lcm-spy (a Java GUI, usually on a laptop) needs the rest.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "liblcm-bin")
# The Python package (python/, /usr/lib/python3/dist-packages/ogf) is an extension module for the Python it
# was built with, and returns numpy arrays: recommended, as the robot's daemons need neither.
if(OGF_PYTHON_PACKAGE_FOUND)
  string(APPEND CPACK_DEBIAN_PACKAGE_RECOMMENDS ", python3 (>= ${OGF_PYTHON_VERSION}), "
         "python3 (<< ${OGF_PYTHON_VERSION_NEXT}), python3-numpy")
endif()
set(CPACK_DEBIAN_PACKAGE_SUGGESTS "liblcm-java, libjchart2d-java, default-jre")
set(CPACK_DEBIAN_PACKAGE_CONTROL_EXTRA
    "${PROJECT_SOURCE_DIR}/packaging/debian/conffiles"
    "${PROJECT_SOURCE_DIR}/packaging/debian/postinst"
    "${PROJECT_SOURCE_DIR}/packaging/debian/prerm"
    "${PROJECT_SOURCE_DIR}/packaging/debian/postrm")
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)

include(CPack)
