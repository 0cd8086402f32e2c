"""Ctrl-C during a main-thread locus call inside Blender (run by check_addon.py).

    blender -b --factory-startup --python tests/blender/sigint_in_blender.py -- OUT.json MODULE_DIR MESH

Blender installs its own C handler for SIGINT (background mode: it counts
the break, and exits on the second); Python's is not installed, so nothing
schedules a KeyboardInterrupt. locus raises KeyboardInterrupt itself (as
under plain Python), which is checked here: one signal, sent from the
progress callback while the call runs. Blender's break state lingers
afterwards, so this runs in a Blender of its own and leaves at once.
"""
import json
import os
import signal
import sys

out, module_dir, mesh = sys.argv[sys.argv.index("--") + 1:][:3]
sys.path.insert(0, module_dir)
import locus  # noqa: E402

s = locus.Session(*locus.read_mesh(mesh))
sent = []


def progress(fraction, phase):
    if not sent:
        sent.append(phase)
        os.kill(os.getpid(), signal.SIGINT)


try:
    s.prepare_heat(progress=progress)
    outcome = "finished"
except KeyboardInterrupt:
    outcome = "KeyboardInterrupt"
except locus.Cancelled:
    outcome = "Cancelled"
with open(out, "w") as f:
    json.dump({"sigint": outcome, "sent_during": sent}, f)
sys.stdout.flush()
os._exit(0)
