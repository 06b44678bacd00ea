#!/usr/bin/env bash
# Installs every dependency vx uses on Debian 12 (bookworm), as root. A no-op when all is there.
# Mesa comes from bookworm-backports: bookworm's Mesa 22 lavapipe has no ray tracing.
set -euo pipefail

packages=(
  cmake ninja-build g++ pkg-config git
  libglm-dev glslang-tools libzstd-dev libxxhash-dev libsqlite3-dev libtbb-dev
  libvulkan-dev libvulkan-volk-dev vulkan-validationlayers vulkan-tools
  libglfw3-dev libimgui-dev libstb-dev libcli11-dev libfmt-dev
  libgtest-dev libgmock-dev libbenchmark-dev
  libopenvdb-dev libopenvdb-tools libboost-iostreams-dev libimath-dev
  xvfb xauth
  postgresql libpq-dev
  python3-matplotlib
)
backports_packages=(mesa-vulkan-drivers)

missing() {
  local out=()
  for p in "$@"; do
    dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || out+=("$p")
  done
  echo "${out[@]:-}"
}

have_backports_mesa() {
  local v
  v=$(dpkg-query -W -f='${Version}' mesa-vulkan-drivers 2>/dev/null || true)
  [[ -n "$v" ]] && dpkg --compare-versions "$v" ge 25
}

need=$(missing "${packages[@]}")
if [[ -z "$need" ]] && have_backports_mesa; then
  echo "setup: all dependencies present"
  exit 0
fi

if [[ $(id -u) -ne 0 ]]; then
  echo "setup: missing packages ($need${need:+ }mesa-vulkan-drivers>=25); run as root" >&2
  exit 1
fi

export DEBIAN_FRONTEND=noninteractive
if ! grep -rqs "bookworm-backports" /etc/apt/sources.list /etc/apt/sources.list.d/; then
  cat >/etc/apt/sources.list.d/vx-backports.sources <<'SRC'
Types: deb
URIs: http://deb.debian.org/debian
Suites: bookworm-backports
Components: main
Signed-By: /usr/share/keyrings/debian-archive-keyring.gpg
SRC
fi
apt-get update -qq
if [[ -n "$need" ]]; then
  # shellcheck disable=SC2086
  apt-get install -y -qq --no-install-recommends $need
fi
if ! have_backports_mesa; then
  apt-get install -y -qq --no-install-recommends -t bookworm-backports "${backports_packages[@]}"
fi
echo "setup: done"
