#!/usr/bin/env bash
# Installs dependencies, builds, and renders the shipped example to build/demo.png.
set -euo pipefail
cd "$(dirname "$0")/.."
bash scripts/install-deps.sh
bash scripts/build.sh
./build/frep info examples/rounded_box.vm
./build/frep render examples/rounded_box.vm --size 512 -o build/demo.png
echo "frep: demo image written to $(pwd)/build/demo.png"
