# A Debian package of what `cmake --install` installs: `cpack -G DEB` in the build folder
# writes medspheres_<version>_<arch>.deb. The CLI links the medspheres libraries
# statically; dpkg-shlibdeps turns the shared libraries it needs (assimp, gmp, mpfr,
# yaml-cpp, ...) into the package's Depends.
set(CPACK_PACKAGE_NAME medspheres)
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY
    "Medial sphere sets of triangle meshes and robots, with FCL queries")
set(CPACK_PACKAGE_CONTACT "medspheres maintainers")
set(CPACK_PACKAGE_FILE_NAME_DEFAULT ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION science)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_RESOURCE_FILE_LICENSE ${PROJECT_SOURCE_DIR}/COPYING.GPL-3)
set(CPACK_GENERATOR DEB)
include(CPack)
