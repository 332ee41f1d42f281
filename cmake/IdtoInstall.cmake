include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

install(TARGETS idto EXPORT idtoTargets
  LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
  ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
  RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
  INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/idto DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_BINARY_DIR}/include/idto/version.hpp
  DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/idto)
install(EXPORT idtoTargets NAMESPACE idto:: DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/idto)

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/idtoConfig.cmake.in
  ${PROJECT_BINARY_DIR}/idtoConfig.cmake
  INSTALL_DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/idto)
write_basic_package_version_file(${PROJECT_BINARY_DIR}/idtoConfigVersion.cmake
  VERSION ${PROJECT_VERSION} COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/idtoConfig.cmake ${PROJECT_BINARY_DIR}/idtoConfigVersion.cmake
  DESTINATION ${CMAKE_INSTALL_LIBDIR}/cmake/idto)

# Models and example configurations are data: share/idto.
install(DIRECTORY ${PROJECT_SOURCE_DIR}/models DESTINATION ${CMAKE_INSTALL_DATADIR}/idto)
install(DIRECTORY ${PROJECT_SOURCE_DIR}/examples DESTINATION ${CMAKE_INSTALL_DATADIR}/idto
  FILES_MATCHING PATTERN "*.yaml" PATTERN "*.md")

# The build tree exports the same targets, so a consumer can use an uninstalled build:
# find_package(idto) with idto_DIR (or CMAKE_PREFIX_PATH) pointing at this build folder.
export(EXPORT idtoTargets NAMESPACE idto:: FILE ${PROJECT_BINARY_DIR}/idtoTargets.cmake)
