#!/bin/sh
# isoterra — install the Debian 12 packages the build and the tests need
# (as root; no prompts).  Idempotent.
set -eu
export DEBIAN_FRONTEND=noninteractive
SUDO=""
[ "$(id -u)" -eq 0 ] || SUDO=sudo
$SUDO apt-get update -q
$SUDO apt-get install -y -q --no-install-recommends \
	gcc libc6-dev meson ninja-build pkg-config \
	libegl-dev libgles-dev libpng-dev \
	libegl-mesa0 libgl1-mesa-dri libgbm-dev libdrm-dev
# GeoTIFF heightmaps (optional: the build finds GDAL through pkg-config and
# works without it; with it the GeoTIFF test runs)
$SUDO apt-get install -y -q --no-install-recommends libgdal-dev
