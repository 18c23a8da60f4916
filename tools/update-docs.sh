#!/usr/bin/env bash
# Rewrites the generated parts of the docs from a configured build/ (bash tools/build.sh first):
# the module table of docs/architecture.md, from the CMake targets (cmake/modules.cmake).
set -euo pipefail
cd "$(dirname "$0")/.."
python3 - docs/architecture.md build/generated/module_table.md modules <<'PY'
import sys
page, table, name = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(page, encoding="utf-8").read()
begin, end = f"<!-- {name}:begin -->\n", f"<!-- {name}:end -->"
a, b = text.index(begin) + len(begin), text.index(end)
open(page, "w", encoding="utf-8").write(text[:a] + open(table, encoding="utf-8").read() + text[b:])
print(f"{page}: {name} table updated")
PY
