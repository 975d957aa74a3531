# What an installation holds (`cmake --install`, docs/install.md) and the
# Debian package made of it (`cpack -G DEB`):
#   bin/sabus
#   share/sabus/        the data directory (harness/data, data_dir.hpp), in the
#                       source tree's layout: vectors/ (the suite, profiles/,
#                       examples/, regression/; their READMEs are the vector
#                       and profile schemas), protocol/ERRATA.md (read by the
#                       linter), reports/junit.xsd, reports/SCHEMA.md and
#                       reports/run.schema.json
#   share/man/man1/sabus.1.gz   sabus(1), from sabus --help (cmake/man_page.sh)
#   share/doc/sabus/    README.md, PROXY-LOG.md, docs/ (the guides and the
#                       generated reference)
#   lib/libsabus_protocol.a, include/sabus/protocol/, lib/cmake/sabus/
#                       the protocol library for find_package(sabus),
#                       target sabus::protocol
include(CMakePackageConfigHelpers)

if(SABUS_BUILD_TOOLS)
  install(TARGETS sabus RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
  if(SABUS_MAN_PAGE)
    install(FILES ${SABUS_MAN_PAGE} DESTINATION ${CMAKE_INSTALL_MANDIR}/man1)
  endif()
endif()

set(SABUS_INSTALL_DATADIR ${CMAKE_INSTALL_DATADIR}/sabus)
install(DIRECTORY vectors DESTINATION ${SABUS_INSTALL_DATADIR})
install(FILES protocol/ERRATA.md DESTINATION ${SABUS_INSTALL_DATADIR}/protocol)
install(FILES reports/junit.xsd reports/SCHEMA.md reports/run.schema.json DESTINATION ${SABUS_INSTALL_DATADIR}/reports)
install(FILES README.md tools/PROXY-LOG.md DESTINATION ${CMAKE_INSTALL_DOCDIR})
install(DIRECTORY docs/ DESTINATION ${CMAKE_INSTALL_DOCDIR}/docs)

# The protocol library as a CMake package.
set(SABUS_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/sabus)
set_target_properties(sabus_protocol PROPERTIES EXPORT_NAME protocol)
install(TARGETS sabus_protocol EXPORT sabusTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY protocol/include/ DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(EXPORT sabusTargets NAMESPACE sabus:: DESTINATION ${SABUS_INSTALL_CMAKEDIR})
configure_package_config_file(cmake/sabusConfig.cmake.in ${PROJECT_BINARY_DIR}/sabusConfig.cmake
                              INSTALL_DESTINATION ${SABUS_INSTALL_CMAKEDIR})
# 0.x: a new minor version may change the API.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/sabusConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/sabusConfig.cmake ${PROJECT_BINARY_DIR}/sabusConfigVersion.cmake
        DESTINATION ${SABUS_INSTALL_CMAKEDIR})

# The Debian package: everything above under /usr, its Depends computed by
# dpkg-shlibdeps from the libraries the binary links (yaml-cpp,
# libserialport, fmt, libstdc++, ...).
set(SABUS_PACKAGE_CONTACT "sabus maintainers <sabus@localhost>" CACHE STRING
    "Maintainer field of the Debian package (\"Name <address>\")")
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME sabus)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_CONTACT ${SABUS_PACKAGE_CONTACT})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "SAbus conformance and fuzz test harness for the RC3000 antenna controller")
set(CPACK_PACKAGE_DESCRIPTION
    "The sabus command runs the SAbus conformance vector suite against a Research Concepts RC3000 antenna "
    "controller on a serial port or a TCP serial server, or against its built-in reference controller; "
    "fuzzes a live controller; serves a simulated controller; proxies and decodes bench sessions; and writes "
    "JSON, JUnit, HTML and Markdown reports. With the vectors, device profiles and errata in /usr/share/sabus, "
    "and the protocol library for find_package(sabus).")
string(REPLACE ";" "" CPACK_PACKAGE_DESCRIPTION "${CPACK_PACKAGE_DESCRIPTION}")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION electronics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
include(CPack)
