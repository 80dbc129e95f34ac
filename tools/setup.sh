#!/usr/bin/env bash
# Installs everything hrpp needs to build, test and run on Debian 12 (bookworm) or Debian 13
# (trixie), from Debian packages only; any other system is refused with one line.
# Idempotent: does nothing when all packages are present. Uses sudo when not run as root.
# Both releases get the same lavapipe, Mesa 25 (ray queries): Debian 13's own, and on Debian 12
# the one in bookworm-backports (Debian's official backports), whose source this adds.
# clang, llvm and libclang-rt-dev are the release's default LLVM (14 or 19): llvm puts
# llvm-symbolizer in /usr/bin, where the asan preset points the sanitizers; without it their
# reports have no function names and no suppression matches.
set -euo pipefail

packages=(
  build-essential cmake pkg-config git ca-certificates
  libvulkan-dev mesa-vulkan-drivers vulkan-tools vulkan-validationlayers
  glslang-tools glslang-dev spirv-tools
  libglm-dev libtinygltf-dev libmeshoptimizer-dev libdraco-dev libstb-dev libopenimageio-dev openimageio-tools
  libgtest-dev libcli11-dev nlohmann-json3-dev libbenchmark-dev libembree-dev
  libassimp-dev libtinyobjloader-dev assimp-testmodels assimp-utils
  python3 python3-numpy python3-matplotlib python3-openimageio parallel openssh-server
  clang llvm libclang-rt-dev
)

# The release, from /etc/os-release; on Debian 12, Mesa comes from bookworm-backports.
release=$( . /etc/os-release 2>/dev/null && echo "${ID:-}-${VERSION_ID:-}" || true)
backports=""
case $release in
  debian-12) backports=bookworm-backports ;;
  debian-13) ;;
  *) echo "setup: supported: Debian 12 (bookworm) and Debian 13 (trixie); this is" \
       "'${release:-unknown}' (/etc/os-release)" >&2
     exit 1 ;;
esac

installed() { dpkg-query -W -f='${Status}' "$1" 2>/dev/null | grep -q "install ok installed"; }
mesa_major() { dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null | sed 's/^[0-9]*://; s/\..*//'; }

missing=()
for p in "${packages[@]}"; do
  installed "$p" || missing+=("$p")
done
mesa_missing=0
if [ -n "$backports" ] && [ "$(mesa_major)" != 25 ]; then
  mesa_missing=1
  missing=("${missing[@]/mesa-vulkan-drivers}")
fi
read -r -a missing <<<"${missing[*]}"
if [ ${#missing[@]} -eq 0 ] && [ "$mesa_missing" = 0 ]; then
  echo "setup: all ${#packages[@]} packages present ($release)"
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

# The mirror this machine's apt uses (deb822 sources or the classic list).
mirror() {
  { awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/*.sources 2>/dev/null || true
    awk '$1 == "deb" {for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' \
      /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null || true; } | head -n 1
}
if [ "$mesa_missing" = 1 ] && ! grep -rqs "$backports" /etc/apt/sources.list /etc/apt/sources.list.d; then
  url=$(mirror)
  echo "setup: adding $backports (${url:-http://deb.debian.org/debian}) for Mesa 25"
  echo "deb ${url:-http://deb.debian.org/debian} $backports main" |
    "${sudo[@]}" tee /etc/apt/sources.list.d/hrpp-backports.list >/dev/null
fi

what=${missing[*]:-}
[ "$mesa_missing" = 1 ] && what="$what mesa-vulkan-drivers (Mesa 25, from $backports)"
echo "setup: installing ${what# }"
# openssh-server is there for sshd, which study/tests/remote_sweep_test.sh starts on loopback ports of
# its own; the package's system service is not wanted, so a policy-rc.d keeps it from starting
# while it installs and, where systemd runs, the service is disabled afterwards.
installing_sshd=0
[[ " ${missing[*]} " == *" openssh-server "* && ! -e /usr/sbin/policy-rc.d ]] && installing_sshd=1
if [ "$installing_sshd" = 1 ]; then
  printf '#!/bin/sh\nexit 101\n' | "${sudo[@]}" tee /usr/sbin/policy-rc.d >/dev/null
  "${sudo[@]}" chmod +x /usr/sbin/policy-rc.d
  trap '"${sudo[@]}" rm -f /usr/sbin/policy-rc.d' EXIT
fi
apt_install() {
  "${sudo[@]}" env DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends \
    "$@" >/dev/null
}
"${sudo[@]}" apt-get update -qq
[ ${#missing[@]} -eq 0 ] || apt_install "${missing[@]}"
if [ "$mesa_missing" = 1 ]; then
  apt_install -t "$backports" mesa-vulkan-drivers
  [ "$(mesa_major)" = 25 ] ||
    { echo "setup: mesa-vulkan-drivers from $backports is not Mesa 25" >&2; exit 1; }
fi
if [ "$installing_sshd" = 1 ] && [ -d /run/systemd/system ]; then
  "${sudo[@]}" systemctl disable --quiet ssh.service ssh.socket 2>/dev/null || true
  echo "setup: openssh-server's service disabled (the tests run sshd on their own ports)"
fi
echo "setup: done"
