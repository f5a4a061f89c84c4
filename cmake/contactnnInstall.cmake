# Install rules and the package config: after `cmake --install`, a finite-element code writes
#   find_package(contactnn REQUIRED)
#   target_link_libraries(fe PRIVATE contactnn::c)        # C, Fortran (shared library, no dependencies)
#   target_link_libraries(fe PRIVATE contactnn::runtime)  # C++: the local search and the network file reader
#                                                         # (static libraries, HDF5), nothing of the trainer
#   target_link_libraries(fe PRIVATE contactnn::contact)  # C++: the contact search handle,
#                                                         # contactnn::contact::ContactSearch (contact_search.hpp)
#   find_package(contactnn REQUIRED COMPONENTS mpi)       # where contactnn was built with MPI:
#   target_link_libraries(fe PRIVATE contactnn::mpi)      # C++ DistributedContactSearch; contactnn::mpi_c: C
#                                                         # (contactnn/contactnn_mpi.h) and Fortran
# and includes <contactnn/contactnn.h> (C) or <contactnn/search/local_search.hpp>, <contactnn/io/...> (C++).
# Components: contactnn_runtime (libcontactnn_c.so), contactnn_development (headers, static libraries, the
# CMake package, the Fortran module's source), contactnn_apps (gen-configs, train-net, evaluate-net,
# scene-study).
include(CMakePackageConfigHelpers)

set(CONTACTNN_INSTALL_CMAKEDIR ${CMAKE_INSTALL_LIBDIR}/cmake/contactnn CACHE STRING
    "Where the CMake package (contactnnConfig.cmake) is installed, relative to the prefix")
mark_as_advanced(CONTACTNN_INSTALL_CMAKEDIR)

# The C++ modules an FE code may use, and everything they link: the run-time search and network files, and
# the contact search handle (lib/contact: contact::ContactSearch, issue 38). Not installed: eval, study,
# history (the tools' own libraries) and the command-line layer.
# Headers go to include/contactnn/<module>/; the targets' include path holds both include/ (a consumer's
# <contactnn/<module>/<file>.hpp>) and include/contactnn (the headers' own "<module>/<file>.hpp").
# lib/io/plan_file.hpp is left out: its target (plan_file, the scene plan) is the tools' and libcontactnn_c's, not
# installed.
set(contactnn_installed_modules core geometry projection dataset mlp mesh io search contact)
foreach(module IN LISTS contactnn_installed_modules)
  install(DIRECTORY ${PROJECT_SOURCE_DIR}/lib/${module}/
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/contactnn/${module}
          COMPONENT contactnn_development
          FILES_MATCHING PATTERN "*.hpp" PATTERN "*.h" PATTERN "plan_file.hpp" EXCLUDE)
endforeach()
# One target per module, and three more: lib/mlp's network without the trainer (network), lib/io's network
# files without the other formats (network_file), and the C++ run-time target over search and network_file
# (runtime, an INTERFACE target). contactnn::runtime's link set is checked by tests/capi (consumer_check.py).
set(contactnn_installed_targets ${contactnn_installed_modules} network network_file runtime)
list(TRANSFORM contactnn_installed_targets PREPEND contactnn_)
foreach(target IN LISTS contactnn_installed_targets)
  string(REGEX REPLACE "^contactnn_" "" name ${target})
  set_target_properties(${target} PROPERTIES EXPORT_NAME ${name})
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

# The MPI component (lib/mpi, built where CMake found MPI): contactnn::mpi (C++, static, over contactnn::contact)
# and contactnn::mpi_c (C, a shared library beside libcontactnn_c), in export sets of their own so that the
# package needs MPI only where a consumer asks for the component (contactnnConfig.cmake).
if(TARGET contactnn_mpi)
  set_target_properties(contactnn_mpi PROPERTIES EXPORT_NAME mpi)
  set_target_properties(contactnn_mpi_c PROPERTIES EXPORT_NAME mpi_c)
  install(FILES ${PROJECT_SOURCE_DIR}/lib/mpi/distributed_contact_search.hpp
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/contactnn/mpi COMPONENT contactnn_development)
  install(FILES ${PROJECT_SOURCE_DIR}/lib/mpi/contactnn/contactnn_mpi.h ${PROJECT_SOURCE_DIR}/lib/mpi/contactnn_mpi.f90
          DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/contactnn COMPONENT contactnn_development)
  install(TARGETS contactnn_mpi EXPORT contactnnMpiTargets
          ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT contactnn_development)
  install(TARGETS contactnn_mpi_c EXPORT contactnnMpiCTargets
          LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR} COMPONENT contactnn_runtime
                  NAMELINK_COMPONENT contactnn_development)
  install(EXPORT contactnnMpiTargets NAMESPACE contactnn:: DESTINATION ${CONTACTNN_INSTALL_CMAKEDIR}
          COMPONENT contactnn_development)
  install(EXPORT contactnnMpiCTargets NAMESPACE contactnn:: DESTINATION ${CONTACTNN_INSTALL_CMAKEDIR}
          COMPONENT contactnn_development)
endif()

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
