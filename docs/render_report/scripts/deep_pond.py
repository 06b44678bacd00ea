"""The deep pond's volume (absorption-2026-12-06/make_deep_pond.py: 96 x 24 x 96, u8, x fastest,
then y, then z), for the scripts that build on it (make_lamp_pond.py, make_dock_pond.py): written to
a file, read back, changed with put(), written again with save()."""
import os
import subprocess
import sys

X, Y, Z = 96, 24, 96
HERE = os.path.dirname(os.path.abspath(__file__))


def deep_pond(out):
    """Writes the deep pond to `out` and returns its blocks."""
    script = os.path.join(HERE, "..", "absorption-2026-12-06", "make_deep_pond.py")
    subprocess.run([sys.executable, script, out], check=True)
    vol = bytearray(open(out, "rb").read())
    assert len(vol) == X * Y * Z
    return vol


def put(vol, x, y, z, block):
    vol[x + X * (y + Y * z)] = block


def save(vol, out):
    open(out, "wb").write(vol)
