"""A locus call off Blender's main thread: progress, Esc, and the result handed back.

Blender's data may be touched only on the main thread, so an operator reads
the mesh into NumPy arrays first (main thread), runs the locus call on a
worker thread (locus releases the GIL while computing, so the interface stays
live), and writes the result when the call is done (main thread again). Esc
sets the flag the progress callback returns: locus stops at its next cancel
check and raises locus.Cancelled, and nothing is written.
"""
import threading

_MAIN_THREAD = threading.main_thread().ident


class Job:
    def __init__(self, work):
        self.fraction = 0.0
        self.phase = ""
        self.cancel = False
        self.done = False
        self.result = None
        self.error = None
        self._work = work
        self._thread = threading.Thread(target=self._run, name="locus-job", daemon=True)

    def progress(self, fraction, phase):
        """The locus progress callback: records where the call is; True asks it to stop."""
        self.fraction = float(fraction)
        self.phase = str(phase)
        return self.cancel

    def start(self):
        self._thread.start()

    def _run(self):
        try:
            self.result = self._work(self.progress)
        except BaseException as e:  # handed to the main thread, reported there
            self.error = e
        finally:
            self.done = True


def main_thread_progress(window_manager):
    """A progress callback for a call run on the main thread (background mode, redo)."""
    def progress(fraction, phase):
        if threading.get_ident() == _MAIN_THREAD:
            window_manager.progress_update(int(1000 * min(max(float(fraction), 0.0), 1.0)))
        return False
    return progress
