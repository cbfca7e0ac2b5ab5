#!/usr/bin/env bash
# The main job: installs, builds, and runs the demo on the bundled data; results in Output/:
# collision tables of the bundled body, then 200 guides simulated with both models under a
# head shake, stored in HDF5, with pictures, an energy plot and a ParaView state; then a
# full head of rendered hair from the guides.
# The demo runs the plugin only (pvpython scripts): it builds that, not the tests and
# benchmarks that `bash Scripts/test.sh` builds.
HAIR_TARGETS="HairDynamics"
source "$(dirname "${BASH_SOURCE[0]}")/common.sh"
OUT="${HAIR_OUTPUT_DIR:-$ROOT/Output}"
# Debian's ParaView renders only through X: xvfb-run gives it a display. Each in a session of
# its own (setsid -w waits and passes the exit status on): Debian's pvpython starts MPI as a
# singleton, and the daemon (orted) left by one script was seen to stop the next one's X
# server, which shared its process group ("bad X server connection" seconds into a script).
setsid -w xvfb-run -a -s "-screen 0 1280x1024x24" pvpython "$ROOT/Scripts/demo.py" "$PLUGIN" "$OUT"
setsid -w xvfb-run -a -s "-screen 0 1280x1024x24" pvpython "$ROOT/Scripts/demo_simulation.py" "$PLUGIN" "$OUT"
setsid -w xvfb-run -a -s "-screen 0 1280x1024x24" pvpython "$ROOT/Scripts/demo_hair.py" "$PLUGIN" "$OUT"
