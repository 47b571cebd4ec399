#!/bin/sh
# isoterra — install the Debian 12 packages the build and the tests need
# (as root; no prompts).  Idempotent.
set -eu
export DEBIAN_FRONTEND=noninteractive
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
# as a user: through sudo, which drops the environment (DEBIAN_FRONTEND
# with it); as root (a container, a board's first boot) there may be none
[ -z "$SUDO" ] || SUDO="sudo env DEBIAN_FRONTEND=noninteractive"
[ -z "$SUDO" ] || command -v sudo >/dev/null 2>&1 || { echo "$0: run it as root, or install sudo" >&2; exit 1; }
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
	gcc libc6-dev meson ninja-build pkg-config \
	libegl-dev libgles-dev libpng-dev libexpat1-dev \
	libegl-mesa0 libgl1-mesa-dri libgbm-dev libdrm-dev
# a second GL driver for the GPU tests: zink (Mesa's OpenGL on Vulkan, in
# libgl1-mesa-dri) on lavapipe, the Vulkan software rasterizer of this package
# (tools/test-all.sh's zink suite: LIBGL_ALWAYS_SOFTWARE=1
# MESA_LOADER_DRIVER_OVERRIDE=zink)
$SUDO apt-get install -y -q --no-install-recommends mesa-vulkan-drivers
# the hardware layer (hal/): GPIO controls (libgpiod); the VM tests (tests/vm/,
# suite 'vm'): QEMU, Debian's kernel with headers and source (gpio-sim is
# built out of tree), busybox + cpio for the initramfs, v4l-utils (vivid)
$SUDO apt-get install -y -q --no-install-recommends \
	libgpiod-dev v4l-utils make \
	qemu-system-x86 busybox-static cpio kmod linux-image-amd64 linux-headers-amd64 linux-source-6.1
# systemd's notifications for the kiosk unit (Type=notify, the watchdog;
# optional: the build works without libsystemd and sends none)
$SUDO apt-get install -y -q --no-install-recommends libsystemd-dev
# the kernel's display hotplug events for the gbm backend (optional: libudev)
$SUDO apt-get install -y -q --no-install-recommends libudev-dev
# the libFuzzer harnesses of tests/fuzz/ (tools/fuzz.sh): Debian's clang,
# and its compiler-rt (libFuzzer, the sanitizers; only recommended by clang)
$SUDO apt-get install -y -q --no-install-recommends clang libclang-rt-dev
# GeoTIFF heightmaps (optional: the build finds GDAL through pkg-config and
# works without it; with it the GeoTIFF test runs)
$SUDO apt-get install -y -q --no-install-recommends libgdal-dev
# the display backends (meson options -Dgbm/-Dwayland/-Dx11, auto)
$SUDO apt-get install -y -q --no-install-recommends \
	libwayland-dev wayland-protocols libx11-dev libx11-xcb-dev libxcb1-dev libxcb-shm0-dev
# the display tests: X11 in Xvfb, Wayland in Weston, KMS in a real kernel
# under QEMU (tests/display, tests/vm)
$SUDO apt-get install -y -q --no-install-recommends \
	xvfb x11-apps weston \
	qemu-system-x86 busybox-static linux-image-amd64 kmod cpio python3 \
	kmscube glmark2-es2-drm
# Debian 13 in a chroot, the arm64 cross build and the Debian package
# (tools/debian13.sh, arm64.sh, debpkg.sh): debootstrap fetches everything
# else from Debian's archive into build-d13/
$SUDO apt-get install -y -q --no-install-recommends debootstrap
# the Debian 12 package, built on this host by tools/debpkg.sh
$SUDO apt-get install -y -q --no-install-recommends debhelper dpkg-dev fakeroot
# optional, bench only: the peers of build/bench/bench_pipeline (libnoise's
# Perlin fBm, linked when found; VTK's flying edges through python3, found
# at run time).  The build and the tests work without them; python3-vtk9
# pulls VTK, MPI and Qt libraries (~210 MB on Debian 12).
$SUDO apt-get install -y -q --no-install-recommends libnoise-dev python3-vtk9
