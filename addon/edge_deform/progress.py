"""Long work on the main thread (Bind, Solve, Bake, Live's domain switch): Blender's
progress indicator, the wait cursor and what happens in the status bar, while a generator
of stages runs. The tests listen to `progress_listeners`."""

import contextlib

from . import compat


# Callables (kind, text, fraction) told of long work: 'begin', 'update' (a new stage or
# fraction), 'drawn' (the status bar showed `text`: the user saw it) and 'end'.
progress_listeners = []


def _progress(kind, text, fraction):
    for listen in progress_listeners:
        listen(kind, text, fraction)


def _show_status(workspace, text, fraction):
    def draw(layout):
        layout.label(text=text, icon='TIME')
        _progress('drawn', text, fraction)
    compat.status_bar(workspace, draw)


@contextlib.contextmanager
def busy(context, text):
    """Long work on the main thread (Bind, Solve, Bake): Blender's progress indicator and
    wait cursor, and what is happening in the status bar, until the work ends.
    Yields update(fraction, text=None): how far the work got, and what it does now."""
    wm, window, workspace = context.window_manager, context.window, context.workspace
    _progress('begin', text, 0.0)
    wm.progress_begin(0.0, 1.0)
    if window is not None:
        window.cursor_modal_set('WAIT')
    _show_status(workspace, text, 0.0)

    def update(fraction, stage=None):
        wm.progress_update(fraction)
        if stage is not None:
            _show_status(workspace, stage, fraction)
        _progress('update', stage or text, fraction)

    try:
        yield update
    finally:
        wm.progress_end()
        if window is not None:
            window.cursor_modal_restore()
        compat.status_bar(workspace, None)
        _progress('end', text, 1.0)


class Stages:
    """Long work written as a generator of (fraction, text) before each stage, run one
    stage per advance() call, with busy()'s progress, wait cursor and status text from
    the first call until the work ends. Between calls Blender redraws, so the user sees
    what the next stage does before it runs. stop() (idempotent) closes the generator
    early: work written that way touches no bpy data before its last stage."""

    def __init__(self, context, text, steps):
        self.steps, self.stage = steps, text
        self.busy = busy(context, text)
        self.update = self.busy.__enter__()

    def advance(self):
        """Run the next stage: (True, the work's result) when it ended (then stopped),
        else (False, None) with the next stage's text shown. An exception stops it."""
        try:
            fraction, self.stage = next(self.steps)
        except StopIteration as done:
            self.stop()
            return True, done.value
        except BaseException:
            self.stop()
            raise
        self.update(fraction, self.stage)
        return False, None

    def run_to_end(self):
        while True:
            done, result = self.advance()
            if done:
                return result

    def stop(self):
        steps, self.steps = self.steps, None
        if steps is not None:
            steps.close()
            self.busy.__exit__(None, None, None)


def run_steps(context, text, steps):
    """Run long work written as a generator of (fraction, what it does next) in one go
    (scripts, EXEC_DEFAULT), with the progress shown; returns the generator's result."""
    return Stages(context, text, steps).run_to_end()
