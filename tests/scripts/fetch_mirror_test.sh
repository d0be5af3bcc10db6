#!/usr/bin/env bash
# fetch-meshlab-source.sh finds the Debian mirror with either apt sources layout: the one-line
# /etc/apt/sources.list alone (the installer's and debootstrap's), deb822 .sources files alone (the
# containers' and cloud images'), and stops with a message when there is neither.
set -uo pipefail
script=${1:?usage: fetch_mirror_test.sh FETCH_SCRIPT}
work=$(mktemp -d); trap 'rm -rf "$work"' EXIT
fail=0
check() {  # name, expected mirror ("" = must fail with a message)
  local out err rc
  out=$(TREESKEL_APT_ETC="$work/$1" bash "$script" --mirror 2>"$work/err"); rc=$?
  err=$(cat "$work/err")
  if [ -n "$2" ]; then
    if [ $rc -ne 0 ] || [ "$out" != "$2" ]; then echo "FAIL $1: rc=$rc out='$out' err='$err'"; fail=1; fi
  elif [ $rc -eq 0 ] || ! grep -q "no Debian mirror" <<<"$err"; then
    echo "FAIL $1: expected a refusal, rc=$rc out='$out' err='$err'"; fail=1
  fi
}

mkdir -p "$work/oneline/sources.list.d"
cat > "$work/oneline/sources.list" <<'SRC'
# deb cdrom:[Debian GNU/Linux 12.5.0 _Bookworm_]/ bookworm main
deb http://security.debian.org/debian-security bookworm-security main
deb [arch=amd64 signed-by=/usr/share/keyrings/debian-archive-keyring.gpg] http://ftp.de.debian.org/debian/ bookworm main
deb-src http://ftp.de.debian.org/debian/ bookworm main
SRC
check oneline http://ftp.de.debian.org/debian/

mkdir -p "$work/deb822/sources.list.d"
cat > "$work/deb822/sources.list.d/debian.sources" <<'SRC'
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm bookworm-updates
Components: main

Types: deb
URIs: http://deb.debian.org/debian-security
Suites: bookworm-security
Components: main
SRC
check deb822 http://deb.debian.org/debian

mkdir -p "$work/listdir/sources.list.d"
echo "deb https://mirror.example.org/debian bookworm main" > "$work/listdir/sources.list.d/extra.list"
check listdir https://mirror.example.org/debian

mkdir -p "$work/none/sources.list.d"
check none ""
mkdir -p "$work/missing"
check missing ""
exit $fail
