#!/usr/bin/env bash
# Installs everything hrpp needs to build, test and run on Debian 12, from Debian packages only.
# Idempotent: does nothing when all packages are present. Uses sudo when not run as root.
# llvm-14 brings llvm-symbolizer (/usr/lib/llvm-14/bin), which the asan preset points the
# sanitizers at: without it their reports have no function names and no suppression matches.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git ca-certificates
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers
  glslang-tools glslang-dev spirv-tools
  libglm-dev libtinygltf-dev libmeshoptimizer-dev libdraco-dev libstb-dev libopenimageio-dev openimageio-tools
  libgtest-dev libcli11-dev nlohmann-json3-dev libbenchmark-dev libembree-dev
  python3 python3-numpy python3-matplotlib python3-openimageio parallel openssh-server
  clang libclang-rt-14-dev llvm-14
)

missing=()
for p in "${packages[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if [ ${#missing[@]} -eq 0 ]; then
  echo "setup: all ${#packages[@]} packages present"
  exit 0
fi

if [ "$(id -u)" -eq 0 ]; then
  sudo=()
elif command -v sudo >/dev/null 2>&1; then
  sudo=(sudo)
else
  echo "setup: need root or sudo to install: ${missing[*]}" >&2
  exit 1
fi
echo "setup: installing ${missing[*]}"
# openssh-server is there for sshd, which tests/remote_sweep_test.sh starts on loopback ports of
# its own; the package's system service is not wanted, so a policy-rc.d keeps it from starting
# while it installs and, where systemd runs, the service is disabled afterwards.
installing_sshd=0
[[ " ${missing[*]} " == *" openssh-server "* && ! -e /usr/sbin/policy-rc.d ]] && installing_sshd=1
if [ "$installing_sshd" = 1 ]; then
  printf '#!/bin/sh\nexit 101\n' | "${sudo[@]}" tee /usr/sbin/policy-rc.d >/dev/null
  "${sudo[@]}" chmod +x /usr/sbin/policy-rc.d
  trap '"${sudo[@]}" rm -f /usr/sbin/policy-rc.d' EXIT
fi
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
  "${missing[@]}" >/dev/null
if [ "$installing_sshd" = 1 ] && [ -d /run/systemd/system ]; then
  "${sudo[@]}" systemctl disable --quiet ssh.service ssh.socket 2>/dev/null || true
  echo "setup: openssh-server's service disabled (the tests run sshd on their own ports)"
fi
echo "setup: done"
