"""The Dask side of `bindery sweep --dask ADDRESS` (the CLI writes this file and runs it).

Sends each chunk of runs to the cluster as one task. A task runs the bindery binary on the
worker (`bindery sweep FILE --rows RUNS`), the same native runner as the embedded sweep, and
returns its rows as text; the rows are printed here as the tasks finish, for the CLI to store.
A task lost with a worker is run again by Dask on another one; its rows arrive once.

Arguments: ADDRESS BINARY SWEEP_FILE SCENE_FILE_OR_- CHUNKS_FILE (one chunk per line).
"""

import os
import subprocess
import sys
import tempfile


def run_chunk(binary, sweep_text, scene_text, runs):
    """Runs `runs` (e.g. "0-99") of the sweep on this worker with the bindery binary."""
    with tempfile.TemporaryDirectory(prefix="bindery-sweep-") as d:
        sweep = os.path.join(d, "sweep.toml")
        with open(sweep, "w", encoding="utf-8") as f:
            f.write(sweep_text)
        cmd = [binary, "sweep", sweep, "--rows", runs]
        if scene_text is not None:
            scene = os.path.join(d, "scene.toml")
            with open(scene, "w", encoding="utf-8") as f:
                f.write(scene_text)
            cmd += ["--scene-file", scene]
        p = subprocess.run(cmd, capture_output=True, text=True)
        if p.returncode != 0:
            raise RuntimeError(f"{' '.join(cmd)}: {p.stderr.strip()}")
        return p.stdout


def main():
    address, binary, sweep_file, scene_file, chunks_file = sys.argv[1:6]
    binary = os.environ.get("BINDERY_WORKER_BINARY", binary)
    from distributed import Client, as_completed

    with open(sweep_file, encoding="utf-8") as f:
        sweep_text = f.read()
    scene_text = None
    if scene_file != "-":
        with open(scene_file, encoding="utf-8") as f:
            scene_text = f.read()
    with open(chunks_file, encoding="utf-8") as f:
        chunks = [line.strip() for line in f if line.strip()]
    with Client(address, timeout="30s") as client:
        sweep_data, scene_data = client.scatter([sweep_text, scene_text], broadcast=True)
        futures = [
            client.submit(run_chunk, binary, sweep_data, scene_data, runs, pure=False, retries=2)
            for runs in chunks
        ]
        for fut in as_completed(futures):
            out = fut.result()
            sys.stdout.write(out)
            sys.stdout.flush()
            fut.release()


if __name__ == "__main__":
    try:
        main()
    except KeyboardInterrupt:
        sys.exit(130)
    except Exception as e:  # the CLI shows this line
        print(f"dask: {type(e).__name__}: {e}", file=sys.stderr)
        sys.exit(1)
