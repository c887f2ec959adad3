#!/usr/bin/env bash
# flake8 with the repository's .flake8 on the Python of python/, tests/ and docs/studies/.
# Usage: flake8.sh ROOT
set -euo pipefail
cd "$1"
flake8 python tests docs/studies
echo "flake8: python/, tests/ and docs/studies/ are clean"
