#!/usr/bin/env bash
# Puts the source of the installed Debian MeshLab (its src/ and vcglib/, which hold the plugin headers
# Debian's binary package lacks) into DEST, the Debian way: `apt-get source` of the installed version,
# with a private source list read from this machine's own Debian mirror, so apt's configuration is left
# as it is. Needs dpkg-dev; no root. Does nothing when DEST already holds the headers.
# Usage: plugins/meshlab/fetch-meshlab-source.sh DEST
#        plugins/meshlab/fetch-meshlab-source.sh --mirror    print the mirror it would use, and exit
# TREESKEL_APT_ETC names apt's configuration directory (default /etc/apt; the tests point it elsewhere).
set -euo pipefail
trap 'echo "fetch-meshlab-source: failed (exit $?) at: $BASH_COMMAND" >&2' ERR
etc=${TREESKEL_APT_ETC:-/etc/apt}

# The first Debian mirror of the machine's sources: deb822 .sources files (Debian 12's default in
# containers and cloud images) or the one-line sources.list / .list files (what the installer and
# debootstrap write). Globs that match nothing are skipped, so either layout alone is enough.
find_mirror() {
  local f mirror=""
  shopt -s nullglob
  for f in "$etc"/sources.list.d/*.sources; do
    mirror=$(awk '/^URIs:/ {for (i = 2; i <= NF; ++i)
                              if ($i ~ /^(https?|ftp):\/\// && $i !~ /security/) {print $i; exit}}' "$f")
    [ -n "$mirror" ] && break
  done
  if [ -z "$mirror" ]; then
    for f in "$etc"/sources.list "$etc"/sources.list.d/*.list; do
      [ -f "$f" ] || continue
      mirror=$(awk '$1 == "deb" && $0 !~ /security/ {
                      for (i = 2; i <= NF; ++i) if ($i ~ /^(https?|ftp):\/\//) {print $i; exit}}' "$f")
      [ -n "$mirror" ] && break
    done
  fi
  shopt -u nullglob
  printf '%s' "$mirror"
}

if [ "${1:-}" = --mirror ]; then
  mirror=$(find_mirror)
  [ -n "$mirror" ] || { echo "fetch-meshlab-source: no Debian mirror (a 'deb http...' line or a URIs: field) in $etc" >&2; exit 1; }
  echo "$mirror"; exit 0
fi
dest=${1:?usage: fetch-meshlab-source.sh DEST}
[ -f "$dest/src/common/interfaces.h" ] && exit 0

version=$(dpkg-query -W -f='${source:Version}' meshlab 2>/dev/null) || {
  echo "fetch-meshlab-source: the meshlab package is not installed" >&2; exit 1; }
mirror=$(find_mirror)
[ -n "$mirror" ] || { echo "fetch-meshlab-source: no Debian mirror (a 'deb http...' line or a URIs: field) in $etc" >&2; exit 1; }
codename=$(. /etc/os-release && echo "${VERSION_CODENAME:-bookworm}")

work=$(mktemp -d "${TMPDIR:-/tmp}/meshlab-source.XXXXXX")
trap 'rm -rf "$work"' EXIT
mkdir -p "$work/lists/partial"
echo "deb-src [signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] $mirror $codename main" > "$work/src.list"
apt_opts=(-o "Dir::Etc::SourceList=$work/src.list" -o Dir::Etc::SourceParts=/dev/null
          -o "Dir::State::Lists=$work/lists" -o Debug::NoLocking=1)
echo "fetch-meshlab-source: fetching MeshLab $version's source from $mirror" >&2
apt-get "${apt_opts[@]}" -qq update
(cd "$work" && apt-get "${apt_opts[@]}" -qq source "meshlab=$version" >/dev/null 2>&1) || {
  echo "fetch-meshlab-source: apt-get source meshlab=$version failed" >&2; exit 1; }
tree=$(find "$work" -mindepth 1 -maxdepth 1 -type d -name 'meshlab-*' | head -n 1)
[ -f "$tree/src/common/interfaces.h" ] || { echo "fetch-meshlab-source: unexpected source layout" >&2; exit 1; }
mkdir -p "$(dirname "$dest")"
rm -rf "$dest.partial"
mv "$tree" "$dest.partial"
mv "$dest.partial" "$dest"
