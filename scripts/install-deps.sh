#!/usr/bin/env bash
# Installs what plumage needs to build and test on Debian 12, if missing.
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
          libembree-dev libopenimageio-dev openimageio-tools libosd-dev libopenmesh-dev
          libcjson-dev libcmocka-dev fonts-dejavu-core)
missing=()
for p in "${packages[@]}"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0
sudo=""
[ "$(id -u)" -ne 0 ] && sudo="sudo"
echo "installing: ${missing[*]}" >&2
$sudo apt-get update -qq
DEBIAN_FRONTEND=noninteractive $sudo apt-get install -y -qq "${missing[@]}"
