#!/usr/bin/env bash
# Copyright (c) 2026, the activecal authors.
# SPDX-License-Identifier: BSD-3-Clause
# Every source file git tracks names its licence (SPDX) and the copyright
# holder, the same as LICENSE; a file without is named.
set -uo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
grep -q '^BSD 3-Clause License' LICENSE || { echo "FAIL LICENSE is not BSD-3-Clause"; exit 1; }
missing=0
while IFS= read -r f; do
  if ! head -4 "$f" | grep -q 'SPDX-License-Identifier: BSD-3-Clause' ||
     ! head -4 "$f" | grep -q 'Copyright (c) 2026, the activecal authors.'; then
    echo "FAIL $f: no licence header (SPDX-License-Identifier: BSD-3-Clause)"
    missing=$((missing + 1))
  fi
done < <(git ls-files '*.cc' '*.h' '*.py' '*.sh' 'CMakeLists.txt' '*/CMakeLists.txt' '*.cmake')
[ "$missing" -eq 0 ] && echo "ok   every tracked source has its licence header"
exit $((missing > 0))
