#!/usr/bin/env bash
# Installs what plumage needs to build and test on Debian 12, if missing.
#   scripts/install-deps.sh           the build and test dependencies
#   scripts/install-deps.sh --slurm   also Slurm and munge, for the opt-in `slurm`
#                                     tests (CI only: this puts scheduler daemons on
#                                     the machine, which a plain install never does)
#   scripts/install-deps.sh --fuzz    also clang 14 and its compiler-rt (libFuzzer and
#                                     the sanitizers) for the PLUMAGE_FUZZ build
#                                     (docs/robustness.md)
#   scripts/install-deps.sh --video   also ffmpeg, which turns turntable frames into an MP4
#   scripts/install-deps.sh --blender also Blender and the numpy its glTF importer needs, for the
#                                     `blender` tests (docs/assets.md)
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
          libembree-dev libopenimageio-dev openimageio-tools libosd-dev libopenmesh-dev
          libassimp-dev libcjson-dev libcmocka-dev fonts-dejavu-core)
for arg in "$@"; do
    case "$arg" in
    --slurm) packages+=(slurmctld slurmd slurm-client munge) ;;
    --fuzz) packages+=(clang-14 libclang-rt-14-dev) ;;
    --video) packages+=(ffmpeg) ;;
    --blender) packages+=(blender python3-numpy) ;;
    *) echo "usage: $0 [--slurm] [--fuzz] [--video] [--blender]" >&2; exit 2 ;;
    esac
done
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
