#!/usr/bin/env bash
# The jar holds a class for every .lcm type, and scripts/lcm-spy.sh finds them all ("Found N LCM types",
# the type scan lcm-spy's window and its --text table share; without a display the window is refused, so
# the table is started and stopped after its scan). Exit 77 (skip) when no Java runtime is installed.
set -u
src=$1; jar=$2; lcmdir=$3
command -v java >/dev/null || { echo "SKIP: no java runtime"; exit 77; }
[ -f "$jar" ] || { echo "FAIL: $jar was not built"; exit 1; }

expected=0
listing=$(unzip -l "$jar")
for f in "$lcmdir"/*.lcm; do
  pkg=$(sed -n 's/^[[:space:]]*package[[:space:]]*\([A-Za-z0-9_.]*\).*/\1/p' "$f" | head -1)
  for s in $(sed -n 's/^[[:space:]]*struct[[:space:]]*\([A-Za-z0-9_]*\).*/\1/p' "$f"); do
    cls="${pkg//.//}/$s.class"
    expected=$((expected + 1))
    grep -q " $cls\$" <<<"$listing" || { echo "FAIL: $jar has no $cls"; exit 1; }
  done
done
echo "jar lists all $expected types"

out=$(OGF_JAVA_DIR="$(dirname "$jar")" DISPLAY= timeout 15 bash "$src/scripts/lcm-spy.sh" --text \
      --lcm-url='udpm://239.255.76.67:7667?ttl=0' 2>&1)
found=$(grep -o 'Found [0-9]* LCM types' <<<"$out" | head -1)
echo "lcm-spy: ${found:-<nothing>}"
n=$(grep -o '[0-9]*' <<<"$found")
if [ -z "$n" ] || [ "$n" -lt "$expected" ]; then
  echo "FAIL: lcm-spy should find at least $expected types; its output was:"; echo "$out" | head -20
  exit 1
fi
