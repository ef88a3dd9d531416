#!/usr/bin/env bash
# Replace the README's parameter table (between <!-- params --> and <!-- /params -->) with the
# schema's, as `silt params --markdown` prints it. Usage: tools/update_readme_params.sh [SILT]
set -euo pipefail
cd "$(dirname "$0")/.."
silt=${1:-build/silt}
table=$("$silt" params --markdown)
python3 - "$table" <<'PY'
import sys
table = sys.argv[1] + "\n"
text = open("README.md").read()
begin = text.index("<!-- params -->\n") + len("<!-- params -->\n")
end = text.index("<!-- /params -->")
open("README.md", "w").write(text[:begin] + table + text[end:])
PY
