#!/usr/bin/env bash
# Installs the Debian 12 packages npf builds and tests with, if any is missing.
# Runs apt-get as root (directly, or through sudo when not root).
set -euo pipefail
packages=(build-essential cmake ninja-build pkg-config
          libopenimageio-dev openimageio-tools libopencolorio-dev libopenexr-dev
          libeigen3-dev libyaml-cpp-dev libgtest-dev libgmock-dev libbenchmark-dev
          libhdf5-dev python3-dev python3-venv faketime)
missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "install-deps: all ${#packages[@]} packages present"
  exit 0
fi
sudo_cmd=()
[ "$(id -u)" -eq 0 ] || sudo_cmd=(sudo)
echo "install-deps: installing ${missing[*]}"
"${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get update -qq
"${sudo_cmd[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done"
