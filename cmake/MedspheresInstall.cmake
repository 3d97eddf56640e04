# Installs the libraries, headers and CLI, and a package config so that
# find_package(medspheres) gives medspheres::runtime, ::formats, ::mesh, ::robot, ::render,
# ::measure, ::cover, ::bake, ::robot_bake, ::batch, ::options and ::fcl_adapter
# (medspheres_add_library registers each; medspheres_export_headers installs its headers).
include(GNUInstallDirs)
include(CMakePackageConfigHelpers)

get_property(_medspheres_targets GLOBAL PROPERTY MEDSPHERES_EXPORTED_TARGETS)
install(TARGETS ${_medspheres_targets}
        EXPORT medspheresTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(TARGETS medspheres_cli RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
# The mesh import program, beside the CLI (mesh_io.h, "Isolation"); exported as
# medspheres::import, for programs that link the library and keep it beside them.
set_target_properties(medspheres_import PROPERTIES EXPORT_NAME import)
install(TARGETS medspheres_import EXPORT medspheresTargets
        RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR})
install(DIRECTORY ${PROJECT_SOURCE_DIR}/include/medspheres
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_BINARY_DIR}/generated/medspheres/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/medspheres)

set(_cfgdir ${CMAKE_INSTALL_LIBDIR}/cmake/medspheres)
install(EXPORT medspheresTargets NAMESPACE medspheres:: DESTINATION ${_cfgdir})
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/medspheresConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/medspheresConfig.cmake
                              INSTALL_DESTINATION ${_cfgdir})
write_basic_package_version_file(${PROJECT_BINARY_DIR}/medspheresConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/medspheresConfig.cmake
              ${PROJECT_BINARY_DIR}/medspheresConfigVersion.cmake
        DESTINATION ${_cfgdir})
