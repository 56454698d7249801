#!/usr/bin/env bash
# Starts lcm-spy with the ogf message types, so every ogf channel (and bot_core.pose_t) decodes.
#   scripts/lcm-spy.sh [--lcm-url=URL]
# The jar is taken from $OGF_LCM_JAR, else build/share/java, else the installed share/java.
# Works around two Debian 12 facts: lcm-spy's wrapper passes -Xincgc, which JDK 17 refuses
# (lcm-proj/lcm#331), and its charts need libjchart2d-java, which liblcm-java does not pull in.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
jar=${OGF_LCM_JAR:-}
for candidate in "$here/build/share/java/lcmtypes_ogf.jar" "$here/share/java/lcmtypes_ogf.jar" \
                 /usr/local/share/java/lcmtypes_ogf.jar /usr/share/java/lcmtypes_ogf.jar; do
  [ -n "$jar" ] && break
  [ -f "$candidate" ] && jar=$candidate
done
if [ -z "$jar" ] || [ ! -f "$jar" ]; then
  echo "lcm-spy.sh: lcmtypes_ogf.jar not found; build first (cmake --build build) or set OGF_LCM_JAR" >&2
  exit 1
fi
command -v lcm-spy >/dev/null || { echo "lcm-spy.sh: lcm-spy not installed (apt-get install liblcm-bin liblcm-java)" >&2; exit 1; }
[ -f /usr/share/java/jchart2d.jar ] || echo "lcm-spy.sh: warning: libjchart2d-java is missing, charts will not work" >&2
# lcm-spy's type database scans $CLASSPATH as well as its -cp, so the wrapper's classpath stays intact.
export CLASSPATH="$jar${CLASSPATH:+:$CLASSPATH}"
export JDK_JAVA_OPTIONS="${JDK_JAVA_OPTIONS:+$JDK_JAVA_OPTIONS }-XX:+IgnoreUnrecognizedVMOptions"
exec lcm-spy "$@"
