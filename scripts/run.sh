#!/usr/bin/env bash
# The README's main job. At this stage: installs, builds, and shows the ogf message set making a round
# trip over LCM udpm on loopback. It grows into the full drive (simulate, drive, map, score) as the
# capabilities land.
set -euo pipefail
here=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
bash "$here/scripts/install-deps.sh"
bash "$here/scripts/multicast-loopback.sh"
bash "$here/scripts/build.sh"
"$here/build/bin/ogf-bus-check" --lcm-url "udpm://239.255.76.67:7667?ttl=0"
