# Install rules and the package config: after `cmake --install`, a finite-element code writes
#   find_package(contactnn REQUIRED)
#   target_link_libraries(fe PRIVATE contactnn::c)        # C, Fortran (shared library, no dependencies)
#   target_link_libraries(fe PRIVATE contactnn::search)   # C++: the local search (static)
#   target_link_libraries(fe PRIVATE contactnn::io)       # C++: network files (static, HDF5)
# Components: contactnn_runtime (libcontactnn_c.so), contactnn_development (headers, static libraries, the
# CMake package, the Fortran module's source), contactnn_apps (gen-configs, train-net, evaluate-net,
# scene-study).
include(CMakePackageConfigHelpers)

set(CONTACTNN_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/contactnn CACHE STRING
    "Where the CMake package (contactnnConfig.cmake) is installed, relative to the prefix")
mark_as_advanced(CONTACTNN_INSTALL_CMAKEDIR)

# The C++ modules an FE code may use, and everything they link: the run-time search and network files.
# Not installed: contact, eval (the tools' own libraries) and the command-line layer.
set(contactnn_installed_modules core geometry projection dataset mlp mesh io search)
foreach(module IN LISTS contactnn_installed_modules)
  set_target_properties(contactnn_${module} PROPERTIES EXPORT_NAME ${module})
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/${module}/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/contactnn/${module}
          COMPONENT contactnn_development
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h")
  list(APPEND contactnn_installed_targets contactnn_${module})
endforeach()
# Both are named by the libraries above and are installed empty (see the top CMakeLists.txt).
set_target_properties(contactnn_flags PROPERTIES EXPORT_NAME flags)
set_target_properties(contactnn_warnings PROPERTIES EXPORT_NAME warnings)

install(TARGETS contactnn_flags contactnn_warnings ${contactnn_installed_targets} contactnn_c
        EXPORT contactnnTargets
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT contactnn_runtime
                NAMELINK_COMPONENT contactnn_development
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT contactnn_development)
install(FILES ${PROJECT_SOURCE_DIR}/lib/capi/contactnn/contactnn.h ${PROJECT_SOURCE_DIR}/lib/capi/contactnn.f90
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/contactnn COMPONENT contactnn_development)
install(EXPORT contactnnTargets NAMESPACE contactnn:: DESTINATION ${CONTACTNN_INSTALL_CMAKEDIR}
        COMPONENT contactnn_development)

set(CONTACTNN_FORTRAN_SOURCE_DIR ${CMAKE_INSTALL_INCLUDEDIR}/contactnn)
configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/contactnnConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/contactnnConfig.cmake
                              INSTALL_DESTINATION ${CONTACTNN_INSTALL_CMAKEDIR}
                              PATH_VARS CONTACTNN_FORTRAN_SOURCE_DIR)
# 0.x: a new minor version may change the interface.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/contactnnConfigVersion.cmake
                                 COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/contactnnConfig.cmake ${PROJECT_BINARY_DIR}/contactnnConfigVersion.cmake
        DESTINATION ${CONTACTNN_INSTALL_CMAKEDIR} COMPONENT contactnn_development)

install(TARGETS gen-configs train-net evaluate-net scene-study RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR}
        COMPONENT contactnn_apps)
