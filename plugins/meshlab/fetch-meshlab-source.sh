#!/usr/bin/env bash
# Puts the source of the installed Debian MeshLab (its src/ and vcglib/, which hold the plugin headers
# Debian's binary package lacks) into DEST, the Debian way: `apt-get source` of the installed version,
# with a private source list read from this machine's own Debian mirror, so apt's configuration is left
# as it is. Needs dpkg-dev; no root. Does nothing when DEST already holds the headers.
# Usage: plugins/meshlab/fetch-meshlab-source.sh DEST
set -euo pipefail
dest=${1:?usage: fetch-meshlab-source.sh DEST}
[ -f "$dest/src/common/interfaces.h" ] && exit 0

version=$(dpkg-query -W -f='${source:Version}' meshlab 2>/dev/null) || {
  echo "fetch-meshlab-source: the meshlab package is not installed" >&2; exit 1; }

# The first Debian mirror of the machine's sources (deb822 .sources files or one-line .list files).
mirror=""
for f in /etc/apt/sources.list.d/*.sources; do
  [ -f "$f" ] || continue
  mirror=$(awk '/^URIs:/ && $2 !~ /security/ {print $2; exit}' "$f")
  [ -n "$mirror" ] && break
done
if [ -z "$mirror" ]; then
  mirror=$(cat /etc/apt/sources.list /etc/apt/sources.list.d/*.list 2>/dev/null |
           awk '$1 == "deb" && $0 !~ /security/ {for (i = 2; i <= NF; ++i) if ($i ~ /^[a-z]+:\/\//) {print $i; exit}}')
fi
[ -n "$mirror" ] || { echo "fetch-meshlab-source: no Debian mirror found in /etc/apt" >&2; exit 1; }
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
