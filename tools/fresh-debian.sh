#!/usr/bin/env bash
# Runs one of the README's commands as a new user would: in a fresh Debian root (debootstrap
# --variant=minbase: no compiler, nothing but apt; Debian 12 bookworm, or Debian 13 with
# SUITE=trixie), in a clean clone of this repository's committed HEAD (uncommitted changes are
# not in it), as root. Prints the command's last 25 lines of output, then one line with its exit
# status and time, and exits with that status.
# Needs root (debootstrap, chroot, bind mounts) and the Debian mirror this machine's apt uses.
# The base root is made once per release (about 2 minutes) and cached as a tarball in
# $HRPP_FRESH_CACHE (default /var/tmp/hrpp-fresh); each run unpacks it anew and removes it.
# Usage: [SUITE=bookworm|trixie] tools/fresh-debian.sh [COMMAND]
#        (default: tools/test.sh on bookworm; e.g. SUITE=trixie tools/fresh-debian.sh tools/demo.sh)
set -euo pipefail

case ${1:-} in
  -h|--help) sed -n '2,11p' "$0" | sed 's/^# \{0,1\}//'; exit 0 ;;
esac
cmd=${1:-tools/test.sh}
repo=$(cd "$(dirname "$0")/.." && pwd)
cache=${HRPP_FRESH_CACHE:-/var/tmp/hrpp-fresh}
suite=${SUITE:-bookworm}
case $suite in
  bookworm) release="Debian 12" ;;
  trixie) release="Debian 13" ;;
  *) echo "fresh-debian: SUITE=$suite: supported are bookworm (Debian 12) and trixie (13)" >&2
     exit 2 ;;
esac
base=$cache/$suite-minbase.tar

fail() { echo "fresh-debian: $*" >&2; exit 2; }
[ "$(id -u)" -eq 0 ] || fail "needs root (debootstrap, chroot and bind mounts)"
if ! command -v debootstrap >/dev/null 2>&1; then
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq debootstrap \
    >/dev/null || fail "cannot install debootstrap"
fi
mkdir -p "$cache"

# The mirror this machine's apt uses (deb822 sources or the classic list).
mirror() {
  { awk '/^URIs:/ {print $2; exit}' /etc/apt/sources.list.d/*.sources 2>/dev/null || true
    awk '$1 == "deb" {for (i = 2; i <= NF; i++) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}' \
      /etc/apt/sources.list 2>/dev/null || true; } | head -n 1
}

if [ ! -f "$base" ]; then
  url=$(mirror)
  [ -n "$url" ] || fail "no Debian mirror found in /etc/apt/sources.list*"
  echo "fresh-debian: making the base root from $url (once; cached in $base)"
  tmp=$(mktemp -d "$cache/debootstrap.XXXX")
  debootstrap --variant=minbase "$suite" "$tmp" "$url" >"$cache/debootstrap-$suite.log" 2>&1 ||
    { rm -rf "$tmp"; fail "debootstrap failed (log: $cache/debootstrap-$suite.log)"; }
  tar -C "$tmp" -cf "$base.partial" . && mv "$base.partial" "$base"
  rm -rf "$tmp"
fi

root=$(mktemp -d "$cache/run.XXXX")
log=$root.log
cleanup() {
  for m in dev/pts dev sys proc; do
    mountpoint -q "$root/$m" && umount -l "$root/$m"
  done
  rm -rf --one-file-system "$root"
}
trap cleanup EXIT
tar -C "$root" -xf "$base"
git clone -q "$repo" "$root/root/hrpp" || fail "cannot clone $repo"
cp /etc/resolv.conf "$root/etc/resolv.conf" 2>/dev/null || true
for m in proc sys dev dev/pts; do mount --bind "/$m" "$root/$m"; done

echo "fresh-debian: '$cmd' in a fresh $release root, clone of $(git -C "$repo" rev-parse --short HEAD)"
start=$(date +%s)
set +e
chroot "$root" /usr/bin/env -i HOME=/root TERM=dumb \
  PATH=/usr/local/sbin:/usr/local/bin:/usr/sbin:/usr/bin:/sbin:/bin \
  bash -lc "cd /root/hrpp && $cmd" </dev/null >"$log" 2>&1
rc=$?
set -e
tail -n 25 "$log"
echo "fresh-debian: '$cmd' on $release exited $rc after $(( $(date +%s) - start )) s (log: $log)"
exit $rc
