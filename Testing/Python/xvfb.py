"""An X server for the GUI tests (plain python3, no ParaView): Xvfb picks a free display
itself and writes its number to a pipe when it is ready to take connections (-displayfd);
it also reclaims lock files left by servers that died. Choosing the number here from
/tmp/.X*-lock ran out of numbers once killed servers had left 39 stale locks."""
import os
import select
import subprocess
import sys


def start(screen):
    """Starts Xvfb with one screen of `screen` (e.g. "1280x1024x24"); returns (process,
    display). Exits the test with a message when no display is reported within 30 s."""
    read_end, write_end = os.pipe()
    xvfb = subprocess.Popen(["Xvfb", "-displayfd", str(write_end), "-screen", "0", screen],
                            pass_fds=(write_end,), stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    os.close(write_end)
    number = b""
    ready, _, _ = select.select([read_end], [], [], 30)
    while ready:
        chunk = os.read(read_end, 16)
        number += chunk
        if not chunk or number.endswith(b"\n"):
            break
        ready, _, _ = select.select([read_end], [], [], 30)
    os.close(read_end)
    if not number.strip().isdigit():
        xvfb.kill()
        sys.exit("Xvfb did not start within 30 s (it reported no display number)")
    return xvfb, ":" + number.strip().decode()


def stop(xvfb):
    """SIGTERM, not SIGKILL: Xvfb then removes its /tmp/.X<n>-lock and socket."""
    xvfb.terminate()
    try:
        xvfb.wait(timeout=10)
    except subprocess.TimeoutExpired:
        xvfb.kill()
        xvfb.wait()
