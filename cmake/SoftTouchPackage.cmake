# `cpack --config BUILD/CPackConfig.cmake` (or `cmake --build BUILD --target package`): a Debian package
# of the installed tree (app/CMakeLists.txt's install rules) under /usr, for a workstation or farm node
# running Debian 12. dpkg-shlibdeps writes its Depends from the programs and plugins themselves, so it
# names exactly the libraries they load. tests/install installs it into a clean folder and runs it.
set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME softtouch)
set(CPACK_PACKAGE_VENDOR "SoftTouch")
set(CPACK_PACKAGE_CONTACT "SoftTouch <softtouch@example.org>")
set(CPACK_PACKAGE_DESCRIPTION_SUMMARY "${PROJECT_DESCRIPTION}")
set(CPACK_PACKAGE_DESCRIPTION
    "An editor (softtouch) for cartoon soft-body animation on free-form deformation lattices, a headless
pipeline (softtouch-cli: bake vertex caches, skins, morphs and lattice caches, render videos, bake clip
libraries on a Slurm farm) and its measurements (softtouch-bench).")
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_SECTION graphics)
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Mesa's drivers are loaded at run time (glvnd), so no ELF names them: the headless render and the
# editor's viewport need them on a machine without a vendor driver.
set(CPACK_DEBIAN_PACKAGE_RECOMMENDS "libgl1-mesa-dri, libegl-mesa0")
include(CPack)
