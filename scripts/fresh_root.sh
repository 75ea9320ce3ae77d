#!/usr/bin/env bash
# A fresh Debian root to try the two set-up commands in, as a new user would (run as root):
#   scripts/fresh_root.sh <bookworm|trixie> <DIR>
# Makes DIR with `debootstrap --variant=minbase` from the mirror in this machine's apt
# sources, bind-mounts /proc, /sys and /dev, trusts this machine's extra certificates (pip
# inside needs them behind a TLS proxy), installs git and clones this checkout into
# DIR/work/main (the clone alone: nothing outside the repository is needed). Then, for example:
#   chroot DIR bash -c 'cd /work/main && time scripts/test.sh'
# Unmount with: umount -R DIR/proc DIR/sys DIR/dev
set -euo pipefail
suite=$1
root=$(realpath -m "$2")
repo=$(cd "$(dirname "$0")/.." && pwd)
mirror=$(cat /etc/apt/sources.list.d/*.sources /etc/apt/sources.list 2>/dev/null |
         grep -v '^ *#' | grep -m1 -oE 'https?://[^ ]*/debian/?( |$)' | tr -d ' ' || true)
mirror=${mirror:-http://deb.debian.org/debian}
command -v debootstrap >/dev/null || apt-get install -y -qq debootstrap
if [ ! -x "$root/usr/bin/apt-get" ]; then
  debootstrap --variant=minbase "$suite" "$root" "$mirror"
fi
for fs in proc sys dev; do
  mountpoint -q "$root/$fs" || mount --rbind "/$fs" "$root/$fs"
done
cp /etc/resolv.conf "$root/etc/resolv.conf"
if ls /usr/local/share/ca-certificates/* >/dev/null 2>&1; then
  mkdir -p "$root/usr/local/share/ca-certificates"
  cp /usr/local/share/ca-certificates/* "$root/usr/local/share/ca-certificates/"
fi
chroot "$root" bash -c 'export DEBIAN_FRONTEND=noninteractive
  apt-get update -qq && apt-get install -y -qq ca-certificates git >/dev/null && update-ca-certificates'
mkdir -p "$root/work"
[ -d "$root/work/main/.git" ] || git clone -q "$repo" "$root/work/main"
echo "fresh_root: $suite in $root; the checkout is $root/work/main"
