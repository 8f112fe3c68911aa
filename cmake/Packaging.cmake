# Installation rules and Debian packages (CPack DEB), one package per service:
#   mocap-node  the camera node (amd64 from the native build, arm64 from the aarch64 cross build)
#   mocap-hub   the live hub and its web console (native build only)
# Each carries its binary, its systemd unit, its example config as a conffile, a sysusers.d file
# (the `mocap` user), a tmpfiles.d file (the directories the service uses) and maintainer scripts
# that create both and enable the unit (deploy/debian/). The unit stays inactive until
# provisioning writes its config (ConditionPathExists), so `dpkg -i` on a fresh Debian leaves an
# installed, enabled service that starts once configured.
#   cmake --build build --target package      -> build/packages/mocap-{node,hub}_VERSION_amd64.deb
#   cmake --build build --target package-arm64 (MOCAP_SUBBUILDS=ON) -> build/packages/mocap-node_VERSION_arm64.deb
include(GNUInstallDirs)

set(deploy_dir ${CMAKE_SOURCE_DIR}/deploy)
set(debian_dir ${deploy_dir}/debian)
# Debian bookworm keeps units and udev rules under /lib (usrmerge makes both paths one).
set(unit_dir /lib/systemd/system)
set(udev_rules_dir /lib/udev/rules.d)

set(mocap_components node)
if(NOT MOCAP_FIRMWARE_ONLY)
    list(APPEND mocap_components hub)
endif()

# The maintainer scripts are the same for both packages but for the unit's name and what each
# package's postinst does beyond the user, directories and unit.
function(_mocap_debian_scripts component)
    set(MOCAP_PACKAGE mocap-${component})
    set(MOCAP_UNIT mocap-${component}.service)
    if(component STREQUAL "node")
        # The GPIO chips go to the gpio group as soon as the rule is installed, not at next boot.
        set(MOCAP_POSTINST_EXTRA "if [ -d /run/udev ]; then udevadm control --reload-rules || true; udevadm trigger --subsystem-match=gpio || true; fi")
    else()
        set(MOCAP_POSTINST_EXTRA "")
    endif()
    set(out ${CMAKE_BINARY_DIR}/debian/${component})
    foreach(script postinst prerm postrm)
        configure_file(${debian_dir}/${script}.in ${out}/${script} @ONLY
            FILE_PERMISSIONS OWNER_READ OWNER_WRITE OWNER_EXECUTE GROUP_READ GROUP_EXECUTE WORLD_READ WORLD_EXECUTE)
    endforeach()
    file(WRITE ${out}/conffiles "/etc/mocap/${component}.conf.example\n")
    string(TOUPPER ${component} upper)
    set(CPACK_DEBIAN_${upper}_PACKAGE_CONTROL_EXTRA ${out}/postinst ${out}/prerm ${out}/postrm ${out}/conffiles PARENT_SCOPE)
endfunction()

foreach(component ${mocap_components})
    set(name mocap-${component})
    install(TARGETS ${name} RUNTIME DESTINATION ${CMAKE_INSTALL_BINDIR} COMPONENT ${component})
    install(FILES ${deploy_dir}/${name}.service DESTINATION ${unit_dir} COMPONENT ${component})
    install(FILES ${deploy_dir}/${component}.conf.example DESTINATION /etc/mocap COMPONENT ${component})
    install(FILES ${debian_dir}/${name}.sysusers DESTINATION lib/sysusers.d RENAME ${name}.conf
        COMPONENT ${component})
    install(FILES ${debian_dir}/${name}.tmpfiles DESTINATION lib/tmpfiles.d RENAME ${name}.conf
        COMPONENT ${component})
    install(FILES ${debian_dir}/copyright DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/${name} COMPONENT ${component})
    _mocap_debian_scripts(${component})
endforeach()
install(FILES ${debian_dir}/60-mocap-gpio.rules DESTINATION ${udev_rules_dir} COMPONENT node)
install(FILES ${CMAKE_SOURCE_DIR}/firmware/README.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/mocap-node
    COMPONENT node)
if(NOT MOCAP_FIRMWARE_ONLY)
    install(FILES ${CMAKE_SOURCE_DIR}/README.md DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/mocap-hub COMPONENT hub)
    install(DIRECTORY ${CMAKE_SOURCE_DIR}/docs/ DESTINATION ${CMAKE_INSTALL_DATADIR}/doc/mocap-hub/docs COMPONENT hub)
    install(DIRECTORY ${CMAKE_SOURCE_DIR}/hub/web/ DESTINATION ${CMAKE_INSTALL_DATADIR}/mocap-hub/web
        COMPONENT hub PATTERN README.md EXCLUDE)
endif()

# ---- CPack: Debian packages, one per component ----
if(CMAKE_CROSSCOMPILING AND CMAKE_SYSTEM_PROCESSOR STREQUAL "aarch64")
    set(deb_arch arm64)
else()
    execute_process(COMMAND dpkg --print-architecture OUTPUT_VARIABLE deb_arch
        OUTPUT_STRIP_TRAILING_WHITESPACE RESULT_VARIABLE dpkg_failed)
    if(dpkg_failed)
        message(STATUS "Packaging: dpkg not found, Debian packages cannot be built here")
        return()
    endif()
endif()

set(CPACK_GENERATOR DEB)
set(CPACK_PACKAGE_NAME mocap)
set(CPACK_PACKAGE_VENDOR "mocap project")
set(CPACK_PACKAGE_CONTACT "mocap maintainers <mocap@localhost>")
set(CPACK_PACKAGE_VERSION ${PROJECT_VERSION})
set(CPACK_PACKAGE_DIRECTORY ${CMAKE_BINARY_DIR}/packages)
set(CPACK_PACKAGING_INSTALL_PREFIX /usr)
set(CPACK_COMPONENTS_ALL ${mocap_components})
set(CPACK_DEB_COMPONENT_INSTALL ON)
set(CPACK_DEBIAN_FILE_NAME DEB-DEFAULT)
set(CPACK_DEBIAN_PACKAGE_ARCHITECTURE ${deb_arch})
set(CPACK_DEBIAN_PACKAGE_RELEASE 1)
set(CPACK_DEBIAN_PACKAGE_SECTION misc)
set(CPACK_DEBIAN_PACKAGE_HOMEPAGE "https://github.com/mocap/mocap")
# Library dependencies from the binaries (dpkg-shlibdeps), plus what the maintainer scripts use.
set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS ON)
# Release binaries without their symbol tables (the hub: 8.5 -> 7.3 MB installed).
set(CPACK_STRIP_FILES ON)
set(CPACK_DEBIAN_PACKAGE_CONTROL_STRICT_PERMISSION ON)
set(CPACK_DEBIAN_NODE_PACKAGE_NAME mocap-node)
set(CPACK_DEBIAN_NODE_PACKAGE_DEPENDS "systemd (>= 247), init-system-helpers")
set(CPACK_DEBIAN_NODE_PACKAGE_RECOMMENDS "chrony, udev")
set(CPACK_COMPONENT_NODE_DESCRIPTION "mocap camera node service
 Captures frames from a camera (V4L2 or libcamera) on a trigger wire, detects the markers and
 sends their centroids to the mocap hub over the authenticated UDP wire.")
set(CPACK_DEBIAN_HUB_PACKAGE_NAME mocap-hub)
set(CPACK_DEBIAN_HUB_PACKAGE_DEPENDS "systemd (>= 247), init-system-helpers")
set(CPACK_DEBIAN_HUB_PACKAGE_RECOMMENDS "chrony, libjs-three")
set(CPACK_COMPONENT_HUB_DESCRIPTION "mocap live hub, tools and web console
 Controls the camera nodes, reconstructs and tracks the markers live, captures sessions and
 serves the HTTP API, the live streams and the web console; also the offline tools
 (calibration, reconstruction, evaluation, simulation).")
# dpkg-shlibdeps reads the arm64 libraries' symbols files from the multiarch -dev packages.
if(deb_arch STREQUAL "arm64" AND CMAKE_CROSSCOMPILING)
    set(CPACK_DEBIAN_PACKAGE_SHLIBDEPS_PRIVATE_DIRS /usr/lib/aarch64-linux-gnu)
endif()
include(CPack)
