#!/usr/bin/env bash
# Installs every Debian package the project needs to build, test and cross-build.
# Idempotent: safe to run again; run as root (or with sudo available) on Debian bookworm.
set -euo pipefail

SUDO=""
if [ "$(id -u)" -ne 0 ]; then
    SUDO="sudo"
fi

HOST_PACKAGES=(
    build-essential cmake ninja-build pkg-config git python3 python3-venv
    # wire protocol: nanopb for the firmware, libprotobuf for the hub
    nanopb libnanopb-dev python3-protobuf protobuf-compiler libprotobuf-dev
    # recorded-frame files (libs/framefile)
    zlib1g-dev
    # test runners
    libcmocka-dev libgtest-dev libgmock-dev
    # hub libraries
    libeigen3-dev libceres-dev libopencv-dev libcli11-dev nlohmann-json3-dev libspdlog-dev libfmt-dev
    # the hub's worker threads inside a frame (oneTBB)
    libtbb-dev
    # the live hub's HTTP + WebSocket API, and three.js for its web console's 3D views
    libcivetweb-dev libjs-three
    # OSC streaming (liblo)
    liblo-dev
    # registration (hub/src/registration): the k-d tree of rigid ICP
    libnanoflann-dev
    # the point-cache test imports mesh driving's .mdd/.pc2 into Blender itself, headless
    blender
    # the web console's browser test (tests/web): headless Chromium and its WebDriver
    chromium chromium-driver
    # the skeleton test's other side for BVH (tests/skeleton): Blender's own importer, headless
    blender
    # node hardware backends
    libgpiod-dev libcamera-dev libsystemd-dev
    # the authenticated wire between hub and nodes (HMAC-SHA-512/256, keys from its CSPRNG)
    libsodium-dev
    # fuzzing and sanitizers
    clang libclang-rt-14-dev
    # aarch64 cross-build and emulation
    gcc-aarch64-linux-gnu g++-aarch64-linux-gnu qemu-user
    # the vivid test: Debian's kernel (with the vivid module) booted in qemu with a busybox
    # initramfs (tests/vivid)
    linux-image-amd64 qemu-system-x86 busybox-static cpio kmod
    # the kernel tests (tests/kernel): vimc.ko and gpio-sim.ko built out of tree from the kernel's
    # source against its headers; libcamera's vimc IPA and cam tool and udevd in the VM
    linux-source-6.1 linux-headers-amd64 libcamera-ipa libcamera-tools udev
    # MJPEG webcams and recorded JPEG frames (required by the node): libjpeg-turbo's TurboJPEG API
    libturbojpeg0-dev
    # measurement
    time zlib1g-dev
    # network namespaces, veth and tc for the node fault tests and the simulated rig
    iproute2
    # systemd-analyze checks the units (label deploy); python3 (above) runs the serve test
    systemd
    # build cache: a fresh clone rebuilds from it in minutes
    ccache
    # Debian packages by CPack (dpkg-shlibdeps computes their library dependencies)
    dpkg-dev
    # provisioning over SSH (deploy/provision), and its test (label deploy): Debian machines
    # made by debootstrap, booted in systemd-nspawn containers (systemd-container)
    openssh-client debootstrap systemd-container
)

# arm64 multiarch libraries that the cross-built firmware and its tests link against.
CROSS_PACKAGES=(
    libnanopb-dev:arm64 libcmocka-dev:arm64 libgpiod-dev:arm64 libsystemd-dev:arm64 zlib1g-dev:arm64
    # the node's authenticated wire
    libsodium-dev:arm64
    # the node's libcamera source, built and linked for the boards it runs on
    libcamera-dev:arm64
    # MJPEG webcams on the boards (required, like libgpiod)
    libturbojpeg0-dev:arm64
)

missing() {
    local pkg
    for pkg in "$@"; do
        dpkg-query -W -f='${Status}' "$pkg" 2>/dev/null | grep -q "install ok installed" || echo "$pkg"
    done
}

if ! dpkg --print-foreign-architectures | grep -qx arm64; then
    $SUDO dpkg --add-architecture arm64
fi

todo=$(missing "${HOST_PACKAGES[@]}" "${CROSS_PACKAGES[@]}")
if [ -n "$todo" ]; then
    $SUDO apt-get update
    # shellcheck disable=SC2086
    DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y --no-install-recommends $todo
fi
echo "install-deps: all packages present"
