"""Runs a meshmark study for the add-on's ``meshmark.study`` operator, in its own process (bpy-free):

    python study_runner.py SPEC OUT

It prints one JSON object per line on stdout: ``{"planned": N, "todo": n}`` first, then
``{"done": k}`` whenever more tasks have finished (``meshmark.study.engine.finished_keys`` on the
output, polled by a thread: the engine's own progress is a log line every 10 s), and finally
``{"summary": {...}}`` or ``{"error": "..."}`` (exit 2 for a bad spec, 1 for anything else).

The engine runs with one worker process and chunks of about a fortieth of the tasks: it writes each
chunk's results as the chunk finishes, so the count of finished tasks grows during the run (run
in-process, ``workers=0``, it computes every chunk before writing any, and the progress would sit at
0 % until the end).
"""
import json
import os
import signal
import sys
import threading


def _stop(signum, frame):
    """Terminated (Esc in Blender): end the worker process too, at once."""
    import multiprocessing
    for child in multiprocessing.active_children():
        child.kill()
    os._exit(128 + signum)


def say(**d):
    print(json.dumps(d, default=str), flush=True)


def main(spec_path, out):
    from meshmark import MeshError
    from meshmark.study import engine, spec as spec_mod
    try:
        sp = spec_mod.load_spec(spec_path)
        keys, _, _ = spec_mod.plan(sp)
    except MeshError as exc:
        say(error=str(exc))
        return 2
    import pathlib
    before = engine.finished_keys(out) if pathlib.Path(out).exists() else set()
    planned = set(keys)
    say(planned=len(keys), todo=len(planned - before))
    stop = threading.Event()

    def poll():
        last = -1
        while not stop.wait(0.3):
            try:
                n = len((engine.finished_keys(out) & planned) - before)
            except Exception:  # a partition being written
                continue
            if n != last:
                say(done=n)
                last = n
    t = threading.Thread(target=poll, daemon=True)
    t.start()
    try:
        todo = len(planned - before)
        chunk = max(1, min(sp.chunk_size, -(-todo // 40)))
        s = engine.run(sp, out, workers=1, progress=False, chunk_size=chunk, log=lambda text: say(log=text))
    except MeshError as exc:
        say(error=str(exc))
        return 2
    finally:
        stop.set()
        t.join()
    say(done=len((engine.finished_keys(out) & planned) - before))
    say(summary=s.to_dict())
    return 0


if __name__ == "__main__":
    signal.signal(signal.SIGTERM, _stop)
    if len(sys.argv) != 3:
        print(__doc__, file=sys.stderr)
        sys.exit(2)
    try:
        sys.exit(main(sys.argv[1], sys.argv[2]))
    except Exception as exc:  # report, do not leave the operator waiting
        say(error=f"{type(exc).__name__}: {exc}")
        sys.exit(1)
