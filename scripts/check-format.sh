#!/usr/bin/env bash
# Fails when a C++ file under engine/, app/ or tests/ differs from what .clang-format makes of it.
# Fix with: git ls-files engine app tests | grep -E '\.(cpp|h)$' | xargs clang-format -i
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
git ls-files -z --cached --others --exclude-standard engine app tests | grep -zE '\.(cpp|h)$' |
  xargs -0 clang-format --dry-run --Werror
