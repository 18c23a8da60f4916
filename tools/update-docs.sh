#!/usr/bin/env bash
# Rewrites the generated parts of the docs from a built build/ (bash tools/build.sh first): the
# module table of docs/architecture.md, from the CMake targets (cmake/modules.cmake), and the
# settings table of the README, from `histoview settings --markdown` (render/settings_schema.cpp).
# The tests architecture_table and cli fail when either copy drifts.
set -euo pipefail
cd "$(dirname "$0")/.."
build/histoview settings --markdown >build/generated/settings_table.md
replace() {
  python3 - "$1" "$2" "$3" <<'PY'
import sys
page, table, name = sys.argv[1], sys.argv[2], sys.argv[3]
text = open(page, encoding="utf-8").read()
begin, end = f"<!-- {name}:begin -->\n", f"<!-- {name}:end -->"
a, b = text.index(begin) + len(begin), text.index(end)
open(page, "w", encoding="utf-8").write(text[:a] + open(table, encoding="utf-8").read() + text[b:])
print(f"{page}: {name} table updated")
PY
}
replace docs/architecture.md build/generated/module_table.md modules
replace README.md build/generated/settings_table.md settings
