# cmake --install: the GI library as a CMake package an engine finds with
#   find_package(bounce 0.2 REQUIRED)
#   target_link_libraries(engine PRIVATE bounce::gi)
# Installed: include/bounce/{gi.h, gi_settings.h, version.h}, libbounce_gi.a
# (the library with its gpu layer and shaders inside) and
# lib/cmake/bounce/{bounceConfig,bounceConfigVersion,bounceTargets}.cmake.
# The package depends on Vulkan alone.
include(CMakePackageConfigHelpers)

set(BOUNCE_CMAKE_DIR ${CMAKE_INSTALL_LIBDIR}/cmake/bounce)

install(TARGETS bounce_gi EXPORT bounceTargets
        ARCHIVE DESTINATION ${CMAKE_INSTALL_LIBDIR}
        LIBRARY DESTINATION ${CMAKE_INSTALL_LIBDIR}
        INCLUDES DESTINATION ${CMAKE_INSTALL_INCLUDEDIR})
install(FILES ${PROJECT_SOURCE_DIR}/include/bounce/gi.h ${PROJECT_SOURCE_DIR}/include/bounce/gi_settings.h
              ${PROJECT_BINARY_DIR}/include/bounce/version.h
        DESTINATION ${CMAKE_INSTALL_INCLUDEDIR}/bounce)
install(EXPORT bounceTargets NAMESPACE bounce:: DESTINATION ${BOUNCE_CMAKE_DIR})

configure_package_config_file(${PROJECT_SOURCE_DIR}/cmake/bounceConfig.cmake.in
                              ${PROJECT_BINARY_DIR}/bounceConfig.cmake INSTALL_DESTINATION ${BOUNCE_CMAKE_DIR})
# 0.x: a minor version may change the interface, so only the same minor matches.
write_basic_package_version_file(${PROJECT_BINARY_DIR}/bounceConfigVersion.cmake COMPATIBILITY SameMinorVersion)
install(FILES ${PROJECT_BINARY_DIR}/bounceConfig.cmake ${PROJECT_BINARY_DIR}/bounceConfigVersion.cmake
        DESTINATION ${BOUNCE_CMAKE_DIR})
