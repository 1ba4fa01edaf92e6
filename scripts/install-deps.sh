#!/usr/bin/env bash
# Installs the Debian 12 packages carom needs to build and test, if any are missing.
set -euo pipefail

packages=(
  g++ cmake make
  libfmt-dev nlohmann-json3-dev libcli11-dev
  libgtest-dev libgmock-dev libbenchmark-dev python3 python3-numpy python3-ase
  pybind11-dev python3-pybind11 python3-dev python3-pytest python3-matplotlib python3-gsd
  libpcg-cpp-dev librapidcheck-dev
  chromium nodejs
)

missing=()
for p in "${packages[@]}"; do
  if ! dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed"; then
    missing+=("$p")
  fi
done
# Some nodejs builds bundle npm; Debian's does not.
if ! command -v npm > /dev/null && ! printf '%s\n' "${missing[@]}" | grep -qx nodejs; then
  missing+=(npm)
fi

if [ ${#missing[@]} -gt 0 ]; then
  echo "Installing missing Debian packages: ${missing[*]}" >&2
  sudo=""
  if [ "$(id -u)" -ne 0 ]; then sudo="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $sudo apt-get update -qq
  $sudo apt-get install -y -qq --no-install-recommends "${missing[@]}"
  command -v npm > /dev/null || $sudo apt-get install -y -qq --no-install-recommends npm
fi

# The browser tests' driver, playwright-core, from the npm registry (it drives Debian's
# chromium; no browser is downloaded).
e2e="$(dirname "$0")/../tests/e2e"
if [ ! -d "$e2e/node_modules/playwright-core" ]; then
  (cd "$e2e" && npm ci --no-audit --no-fund --loglevel=error)
fi
