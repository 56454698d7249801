# CPack pre-build script (CPACK_PRE_BUILD_SCRIPTS): turns the staged `cmake --install` tree, which is
# relative to the /usr prefix, into Debian 12's layout before the .deb is made:
#   usr/etc/ogf/*.yaml      -> etc/ogf/         (conffiles, where ConfigurationDirectory=ogf looks)
#   usr/lib/systemd/system  -> lib/systemd/system (bookworm's unit directory, lintian's expectation)
# and adds the changelog.Debian.gz Debian policy 12.7 asks for. Plain `cmake --install --prefix X` keeps
# the relative layout (X/etc/ogf, X/lib/systemd/system) and is not affected.
if(NOT CPACK_GENERATOR STREQUAL "DEB")
  return()
endif()
set(root "${CPACK_TEMPORARY_INSTALL_DIRECTORY}")
set(usr "${root}${CPACK_PACKAGING_INSTALL_PREFIX}")
if(NOT IS_DIRECTORY "${usr}/bin")
  message(FATAL_ERROR "debian-layout: no ${usr}/bin, the staging layout is not the expected one")
endif()

function(ogf_move_tree from to)
  if(IS_DIRECTORY "${from}")
    get_filename_component(parent "${to}" DIRECTORY)
    file(MAKE_DIRECTORY "${parent}")
    file(RENAME "${from}" "${to}")
  endif()
endfunction()

if(NOT CPACK_PACKAGING_INSTALL_PREFIX STREQUAL "/")
  ogf_move_tree("${usr}/etc" "${root}/etc")
  ogf_move_tree("${usr}/lib/systemd" "${root}/lib/systemd")
endif()

# changelog.Debian.gz: gzip -9n equivalent (no name or time stamp, so the package is reproducible).
set(doc "${usr}/share/doc/${CPACK_DEBIAN_PACKAGE_NAME}")
string(TIMESTAMP date "%a, %d %b %Y %H:%M:%S +0000" UTC)
file(WRITE "${doc}/changelog.Debian"
  "${CPACK_DEBIAN_PACKAGE_NAME} (${CPACK_PACKAGE_VERSION}-${CPACK_DEBIAN_PACKAGE_RELEASE}) unstable; urgency=medium\n\n"
  "  * Package built with CPack from the ogf source tree (see README.md).\n\n"
  " -- ${CPACK_DEBIAN_PACKAGE_MAINTAINER}  ${date}\n")
execute_process(COMMAND gzip -9nf "${doc}/changelog.Debian" RESULT_VARIABLE rc)
if(NOT rc EQUAL 0)
  message(FATAL_ERROR "debian-layout: gzip of changelog.Debian failed (${rc})")
endif()
