#!/bin/sh
# Installs the readers the export tests check vox's files with (package.json
# beside this script: the Khronos glTF validator, a MagicaVoxel reader) from
# the npm registry into DIR/node_modules, at the versions package-lock.json
# pins. Idempotent: a DIR already installed from the same lock file is left
# alone. Needs node and npm (scripts/install-deps.sh installs them).
# Usage: setup.sh DIR
set -eu
here=$(cd "$(dirname "$0")" && pwd)
dir=$1
command -v npm >/dev/null 2>&1 || { echo "setup.sh: npm not found; run scripts/install-deps.sh" >&2; exit 4; }
mkdir -p "$dir"
if [ -d "$dir/node_modules/gltf-validator" ] && [ -d "$dir/node_modules/vox-reader" ] &&
   cmp -s "$here/package-lock.json" "$dir/package-lock.json"; then
  echo "setup.sh: export test tools present in $dir"
  exit 0
fi
cp "$here/package.json" "$here/package-lock.json" "$dir/"
cd "$dir"
if ! npm ci --no-audit --no-fund --loglevel=error >npm.log 2>&1; then
  cat npm.log >&2
  echo "setup.sh: npm could not install the export test tools from $(npm config get registry) (log above);" \
       "the export tests need them and do not run without them" >&2
  if grep -q "CERT\|certificate" npm.log; then
    echo "setup.sh: the registry's TLS certificate was not trusted: behind a proxy that re-signs TLS," \
         "give npm its CA (npm config set cafile /path/to/ca.crt, or NODE_EXTRA_CA_CERTS)" >&2
  fi
  exit 4
fi
rm -f npm.log
echo "setup.sh: installed export test tools in $dir"
