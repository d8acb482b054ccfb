#!/usr/bin/env bash
# The engine's users (cli/, api/, server/) include engine/texopt.h and no other engine header:
# every #include "name.h" there names either texopt.h or a header of cli/, api/ or server/.
set -euo pipefail
cd "${TEXOPT_SOURCE_DIR:?}"
engine_headers=$(find engine -name '*.h' -o -name '*.hpp' | xargs -n1 basename | grep -vx 'texopt.h' | sort -u)
bad=0
for f in cli/*.[ch] api/*.[ch] server/*.[ch]; do
  while read -r name; do
    if grep -qx "$name" <<<"$engine_headers" && [ ! -e "cli/$name" ] && [ ! -e "api/$name" ] && [ ! -e "server/$name" ]; then
      echo "$f includes the internal engine header $name (include texopt.h)" >&2
      bad=1
    fi
  done < <(sed -n 's/^#include "\([^"]*\)".*/\1/p' "$f")
done
[ "$bad" -eq 0 ] && echo "cli/, api/ and server/ include only texopt.h of the engine"
