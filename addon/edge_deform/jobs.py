"""Long work started from the UI as a modal job: one stage per timer tick, so Blender
redraws between stages and Esc cancels (Bind, Solve and Bake use it as a mix-in)."""

from .op_common import call_reporting_errors, error_text, set_header, tell
from .progress import Stages


class StepsJob:
    """Long work from the UI, one step per timer tick (an operator mix-in): between steps
    Blender redraws, so the status bar says what the next step does, the progress
    advances, and Esc cancels. `steps` yields (fraction, text) before each step and
    returns the result; nothing may be written to bpy data before its last step, so a
    cancel leaves the data as it was. The operator defines job_done(context, result) and
    job_cancelled(context)."""

    def start_job(self, context, text, steps):
        self.job = Stages(context, text, steps)
        self.job_area = context.area
        wm = context.window_manager
        self.job_timer = wm.event_timer_add(0.01, window=context.window)
        wm.modal_handler_add(self)
        return {'RUNNING_MODAL'}

    def modal(self, context, event):
        if event.type == 'ESC' and event.value == 'PRESS':
            self.stop_job(context)
            self.job_cancelled(context)
            return {'CANCELLED'}
        if event.type != 'TIMER':
            return {'RUNNING_MODAL'}   # the rest of the UI waits for the work
        try:
            done, result = self.job.advance()
        except Exception as exc:  # noqa: BLE001 - reported; nothing written before the end
            self.stop_job(context)
            tell(self, 'ERROR', error_text(exc))
            return {'CANCELLED'}
        if done:
            self.stop_job(context)
            return call_reporting_errors(self, lambda: self.job_done(context, result))
        self._job_header("%s  (Esc: cancel)" % self.job.stage)
        return {'RUNNING_MODAL'}

    def _job_header(self, text):
        set_header(self.job_area, text)

    def stop_job(self, context):
        context.window_manager.event_timer_remove(self.job_timer)
        self._job_header(None)
        self.job.stop()

    def cancel(self, context):   # the window closes or a file loads
        self.stop_job(context)
