#!/usr/bin/env bash
# Rebuilds three.bundle.min.js (committed; the cargo build needs nothing but this file)
# from the npm packages three and esbuild: the parts of three.js listed in three-entry.js
# plus OrbitControls, bundled as one minified classic script that defines the global THREE.
set -euo pipefail
here=$(cd "$(dirname "$0")" && pwd)
version=${THREE_VERSION:-0.187.0}
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cd "$tmp"
npm init -y >/dev/null
npm install --no-audit --no-fund "three@$version" esbuild@0.28.2 >/dev/null
cp "$here/three-entry.js" .
npx esbuild three-entry.js --bundle --minify --format=iife --global-name=THREE \
    --legal-comments=none \
    --banner:js="/*! three.js ${version} (https://threejs.org), MIT License, Copyright © 2010-2026 three.js authors: see LICENSE-three.txt */" \
    --outfile="$here/three.bundle.min.js"
cp node_modules/three/LICENSE "$here/LICENSE-three.txt"
