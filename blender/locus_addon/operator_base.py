"""What every locus operator shares: read on the main thread, compute off it, write on success.

An operator's prepare(context) reads what it needs from Blender into a Task:
compute(progress) runs the locus call (worker thread when invoked from the
interface, inline in background mode, scripts and redo), apply(context, obj,
result) writes the result (main thread). Errors become operator reports,
never tracebacks; Esc (or locus.Cancelled) ends the operator with nothing
written. The last run's timings are kept in LAST_RUN for scripts and tests.
"""
import time

import bpy

from . import engine, job

LAST_RUN = {}   # bl_idname -> {"compute_s", "total_s", "session"}
_busy = set()   # names of objects with a computation running


class Task:
    def __init__(self, obj, compute, apply, num_vertices=None):
        self.object_name = obj.name
        self.compute = compute
        self.apply = apply
        self.num_vertices = num_vertices  # the vertex count apply() relies on (None: any)
        self.session_how = ""
        self.warnings = []


def addon_preferences(context):
    addon = context.preferences.addons.get(__package__)
    return addon.preferences if addon else None


def load_locus(context):
    prefs = addon_preferences(context)
    return engine.locus(prefs.module_path if prefs else "")


class LocusOperator:
    """Mixin for bpy.types.Operator subclasses that define prepare(context) -> Task."""

    @classmethod
    def poll(cls, context):
        obj = context.active_object
        return obj is not None and obj.type == "MESH"

    def _fail(self, error):
        m = engine._module
        if isinstance(error, KeyboardInterrupt) or (m is not None and isinstance(error, m.Cancelled)):
            self.report({"INFO"}, f"{self.bl_label}: cancelled, nothing was changed")
        elif m is not None and isinstance(error, m.Error):
            self.report({"ERROR"}, f"{self.bl_label}: {error}")
        else:
            self.report({"ERROR"}, f"{self.bl_label}: {type(error).__name__}: {error}")
        return {"CANCELLED"}

    def _prepare(self, context):
        load_locus(context)
        engine.forget(keep=set(bpy.data.objects.keys()))
        obj = context.active_object
        if obj.name in _busy:
            raise RuntimeError(f"a locus computation on '{obj.name}' is still running")
        return self.prepare(context)

    def _finish(self, context, task, result, compute_s, started):
        obj = bpy.data.objects.get(task.object_name)
        if obj is None:
            return self._fail(RuntimeError(f"object '{task.object_name}' was removed meanwhile; nothing written"))
        if task.num_vertices is not None and len(obj.data.vertices) != task.num_vertices:
            return self._fail(RuntimeError(f"the mesh of '{obj.name}' changed meanwhile; nothing written"))
        try:
            message = task.apply(context, obj, result)
        except Exception as e:
            return self._fail(e)
        LAST_RUN[self.bl_idname] = {"compute_s": compute_s, "total_s": time.perf_counter() - started,
                                    "session": task.session_how}
        for w in task.warnings:
            self.report({"WARNING"}, w)
        self.report({"INFO"}, f"{self.bl_label}: {message} ({compute_s:.2f} s, session {task.session_how})")
        return {"FINISHED"}

    def _timed_compute(self, task, progress):
        t0 = time.perf_counter()
        result = task.compute(progress)
        return result, time.perf_counter() - t0

    def execute(self, context):
        started = time.perf_counter()
        try:
            task = self._prepare(context)
        except Exception as e:
            return self._fail(e)
        wm = context.window_manager
        wm.progress_begin(0, 1000)
        _busy.add(task.object_name)
        try:
            result, compute_s = self._timed_compute(task, job.main_thread_progress(wm))
        except BaseException as e:
            return self._fail(e)
        finally:
            _busy.discard(task.object_name)
            wm.progress_end()
        return self._finish(context, task, result, compute_s, started)

    def _interactive(self, context):
        """Whether a window's event loop can drive modal(): else the call runs inline (execute)."""
        return not bpy.app.background and context.window is not None

    def invoke(self, context, event):
        if not self._interactive(context):
            return self.execute(context)
        self._started = time.perf_counter()
        try:
            self._task = self._prepare(context)
        except Exception as e:
            return self._fail(e)
        self._compute_s = 0.0
        task = self._task

        def work(progress):
            result, self._compute_s = self._timed_compute(task, progress)
            return result

        self._job = job.Job(work)
        _busy.add(task.object_name)
        self._job.start()
        wm = context.window_manager
        self._timer = wm.event_timer_add(0.1, window=context.window)
        wm.progress_begin(0, 1000)
        wm.modal_handler_add(self)
        self._status(context, f"{self.bl_label}: starting (Esc cancels)")
        return {"RUNNING_MODAL"}

    def _status(self, context, text):
        if context.workspace is not None:
            context.workspace.status_text_set(text)

    def _end_modal(self, context):
        wm = context.window_manager
        wm.event_timer_remove(self._timer)
        wm.progress_end()
        self._status(context, None)
        _busy.discard(self._task.object_name)

    def modal(self, context, event):
        j = self._job
        if event.type == "ESC" and event.value == "PRESS":
            j.cancel = True
            self._status(context, f"{self.bl_label}: cancelling...")
            return {"RUNNING_MODAL"}
        if not j.done:
            if event.type == "TIMER":
                context.window_manager.progress_update(int(1000 * min(max(j.fraction, 0.0), 1.0)))
                if not j.cancel:
                    self._status(context, f"{self.bl_label}: {100 * j.fraction:.0f}% {j.phase} (Esc cancels)")
            return {"PASS_THROUGH"}
        self._end_modal(context)
        if j.error is not None:
            return self._fail(j.error)
        if j.cancel:  # Esc after the last cancel check: drop the result all the same
            return self._fail(KeyboardInterrupt())
        return self._finish(context, self._task, j.result, self._compute_s, self._started)
