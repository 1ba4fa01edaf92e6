#!/usr/bin/env bash
# Installs the Debian 12 packages carom needs, if any are missing.
#   scripts/install-deps.sh run    what the binary and the Python module need (make demo)
#   scripts/install-deps.sh        all of that, and what the tests and benchmarks need (make test)
set -euo pipefail

what="${1:-test}"
packages=(
  g++ cmake make
  libfmt-dev nlohmann-json3-dev libcli11-dev libpcg-cpp-dev libnanoflann-dev libtomlplusplus-dev
  libopenmpi-dev openmpi-bin
  python3 python3-dev python3-numpy pybind11-dev python3-distributed
)
case "$what" in
  run) ;;
  test)
    packages+=(
      libgtest-dev libgmock-dev libbenchmark-dev librapidcheck-dev
      python3-ase python3-pybind11 python3-pytest python3-matplotlib python3-gsd
      chromium nodejs
    ) ;;
  *) echo "usage: $0 [run|test]" >&2; exit 2 ;;
esac

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# Some nodejs builds bundle npm; Debian's does not.
if [ "$what" = test ] && ! command -v npm > /dev/null &&
   ! printf '%s\n' "${missing[@]}" | grep -qx nodejs; then
  missing+=(npm)
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing missing Debian packages: ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  if [ "$what" = test ]; then
    command -v npm > /dev/null || $sudo apt-get install -y -qq --no-install-recommends npm
  fi
fi
[ "$what" = test ] || exit 0

# The browser tests' driver, playwright-core, from the npm registry (it drives Debian's
# chromium; no browser is downloaded).
e2e="$(dirname "$0")/../tests/e2e"
if [ ! -d "$e2e/node_modules/playwright-core" ]; then
  (cd "$e2e" && npm ci --no-audit --no-fund --loglevel=error)
fi
