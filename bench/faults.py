"""Fault injection: kill (SIGKILL), interrupt (SIGINT) and corrupt `nusselt matrix` runs at
random points and check that every outcome is the identical matrix or a clear refusal.

The scene is the closed cube with n x n patches per face (6 n^2 patches; n = 20: 2 400). A
reference run gives the matrix. Each trial starts a fresh run and, at a random moment within
the reference's wall time, does one of:

* ``kill``      SIGKILL, then ``--resume`` to the end;
* ``interrupt`` SIGINT (exit 130 expected), then ``--resume`` to the end;
* ``corrupt``   SIGKILL, then damages a random file of the checkpoint (truncates or overwrites
                a block, flips one byte, deletes or garbles the manifest, adds a foreign block
                without manifest), then ``--resume``.

Killed and corrupted runs pass ``--checkpoint``, so blocks are written from the first on;
interrupted runs keep the default, in which a short run's blocks are only held in memory until
Ctrl-C writes them.

A resume that ends must give the reference matrix bit for bit and leave no temporary file or
checkpoint behind; a resume that refuses must exit 2 with one line on stderr naming the
checkpoint (no traceback), after which removing what it names and resuming again must give
the reference. Anything else is a failure and is printed.

    python bench/faults.py                  # 30 trials, n = 20
    python bench/faults.py --trials 60 --n 24 --seed 3
"""

from __future__ import annotations

import argparse
import os
import random
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time
from collections import Counter

import numpy as np
from cube import write_cube_obj

import nusselt.io as nio


def run(cmd: list[str], **kw) -> subprocess.CompletedProcess:
    return subprocess.run(cmd, capture_output=True, text=True, check=False, **kw)


def same(a: str, b: str) -> bool:
    x, y = nio.load_npz(a)["matrix"], nio.load_npz(b)["matrix"]
    return (
        x.shape == y.shape
        and np.array_equal(x.indptr, y.indptr)
        and np.array_equal(x.indices, y.indices)
        and np.array_equal(x.data, y.data)
    )


def clear_refusal(p: subprocess.CompletedProcess, partial: str) -> bool:
    err = p.stderr.strip()
    last = err.splitlines()[-1] if err else ""
    return p.returncode == 2 and "Traceback" not in err and last.startswith("nusselt: error:") and partial in last


def corrupt(partial: str, rng: random.Random, foreign: str) -> str:
    files = sorted(os.listdir(partial)) if os.path.isdir(partial) else []
    blocks = [f for f in files if f.startswith("block_") and f.endswith(".npz")]
    how = rng.choice(["truncate", "overwrite", "flip", "drop_manifest", "garble_manifest", "foreign"])
    if how in ("truncate", "overwrite", "flip", "foreign") and not blocks:
        how = "garble_manifest"
    if not files:
        return "nothing to corrupt"
    if how == "foreign":
        victim = os.path.join(partial, rng.choice(blocks))
        shutil.copyfile(os.path.join(foreign, min(f for f in os.listdir(foreign) if f.startswith("block_"))), victim)
        return f"foreign block as {os.path.basename(victim)}"
    if how in ("drop_manifest", "garble_manifest"):
        m = os.path.join(partial, "manifest.json")
        if not os.path.exists(m):
            return "no manifest to damage"
        if how == "drop_manifest":
            os.unlink(m)
        else:
            with open(m, "r+b") as fh:
                data = fh.read()
                fh.seek(rng.randrange(max(1, len(data))))
                fh.write(b"\x00}")
        return how
    victim = os.path.join(partial, rng.choice(blocks))
    size = os.path.getsize(victim)
    with open(victim, "r+b") as fh:
        if how == "truncate":
            fh.truncate(rng.randrange(size))
        elif how == "overwrite":
            fh.seek(rng.randrange(size))
            fh.write(os.urandom(64))
        else:
            at = rng.randrange(size)
            fh.seek(at)
            b = fh.read(1)
            fh.seek(at)
            fh.write(bytes([b[0] ^ 0x10]))
    return f"{how} {os.path.basename(victim)}"


def repair_named(p: subprocess.CompletedProcess, partial: str) -> None:
    """What a user does after a refusal: delete the block it names, or else the directory."""
    m = re.search(r"\((block_\d+\.npz)\) ", p.stderr)
    target = os.path.join(partial, m.group(1)) if m else None
    if target and os.path.exists(target) and "delete that file" in p.stderr:
        os.unlink(target)
    else:
        shutil.rmtree(partial, ignore_errors=True)


def main() -> int:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--n", type=int, default=20, help="patches per cube edge (6 n^2 patches)")
    ap.add_argument("--trials", type=int, default=30)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--block-size", type=int, default=60000)
    ap.add_argument(
        "--kinds",
        nargs="+",
        default=["kill", "interrupt", "corrupt"],
        choices=["kill", "interrupt", "corrupt"],
        help="faults to draw from",
    )
    args = ap.parse_args()
    rng = random.Random(args.seed)
    work = tempfile.mkdtemp(prefix="nusselt-faults-")
    scene = os.path.join(work, "cube.obj")
    write_cube_obj(scene, args.n)
    base = [
        sys.executable,
        "-m",
        "nusselt.cli",
        "matrix",
        scene,
        "-q",
        "--block-size",
        str(args.block_size),
        "--option",
        "tol=1e-6",
    ]
    ref = os.path.join(work, "ref.npz")
    t0 = time.perf_counter()
    subprocess.run(base + ["-o", ref], check=True, capture_output=True)
    t_ref = time.perf_counter() - t0
    # blocks of another scene, for the "foreign" corruption
    other = os.path.join(work, "other.obj")
    write_cube_obj(other, args.n - 1)
    fp = subprocess.Popen(
        [
            sys.executable,
            "-m",
            "nusselt.cli",
            "matrix",
            other,
            "-q",
            "--block-size",
            str(args.block_size),
            "-o",
            os.path.join(work, "other.npz"),
            "--checkpoint",
            os.path.join(work, "other.npz.partial"),
        ],
        stdout=subprocess.DEVNULL,
        stderr=subprocess.DEVNULL,
    )
    foreign = os.path.join(work, "other.npz.partial")
    while fp.poll() is None and not (
        os.path.isdir(foreign) and any(f.startswith("block_") for f in os.listdir(foreign))
    ):
        time.sleep(0.02)
    fp.kill()
    fp.wait()
    print(f"{6 * args.n**2} patches, reference run {t_ref:.1f} s wall; {args.trials} trials", flush=True)

    outcomes: Counter = Counter()
    failures = []
    for t in range(args.trials):
        kind = rng.choice(args.kinds)
        out = os.path.join(work, f"t{t}.npz")
        partial = out + ".partial"
        # kill and corrupt: the checkpoint from the first block (the default writes none in a
        # run's first 10 s); interrupt: the default, so Ctrl-C writes the blocks held till then
        forced = [] if kind == "interrupt" else ["--checkpoint", partial]
        p = subprocess.Popen(base + ["-o", out, *forced], stdout=subprocess.DEVNULL, stderr=subprocess.PIPE, text=True)
        if kind == "corrupt":  # something to corrupt: wait for the first block
            while p.poll() is None and not (
                os.path.isdir(partial) and any(f.startswith("block_") for f in os.listdir(partial))
            ):
                time.sleep(0.01)
            time.sleep(rng.uniform(0.0, 0.5 * t_ref))
        else:
            time.sleep(rng.uniform(0.0, 1.1 * t_ref))
        p.send_signal(signal.SIGINT if kind == "interrupt" else signal.SIGKILL)
        _, err = p.communicate()
        note = f"exit {p.returncode}"
        if kind == "interrupt" and p.returncode == 1 and "KeyboardInterrupt" in err:
            note += " (Ctrl-C during start-up, before the command line took over)"
        elif kind == "interrupt" and p.returncode not in (0, 130, -signal.SIGINT):
            failures.append((t, kind, note, err.strip()[-300:]))
            outcomes["failed"] += 1
            continue
        if kind == "corrupt":
            note += "; " + corrupt(partial, rng, foreign)
        resumed = run(base + ["-o", out, "--resume"] if os.path.isdir(partial) else base + ["-o", out])
        if resumed.returncode == 0:
            result = "identical"
        elif clear_refusal(resumed, partial):
            result = "refused"
            repair_named(resumed, partial)
            again = run(base + ["-o", out, "--resume"] if os.path.isdir(partial) else base + ["-o", out])
            if again.returncode != 0:
                failures.append((t, kind, note + "; after repair", again.stderr.strip()[-300:]))
                outcomes["failed"] += 1
                continue
        else:
            failures.append((t, kind, note, resumed.stderr.strip()[-300:]))
            outcomes["failed"] += 1
            continue
        leftovers = [f for f in os.listdir(work) if f.startswith(f".t{t}.npz") or f == f"t{t}.npz.partial"]
        if not same(ref, out) or leftovers:
            failures.append((t, kind, note, f"differs from the reference or left {leftovers}"))
            outcomes["failed"] += 1
            continue
        outcomes[f"{kind}: {result}"] += 1
        os.unlink(out)
        print(f"trial {t:3d} {kind:9s} {note:45s} -> {result}", flush=True)
    print()
    for k, v in sorted(outcomes.items()):
        print(f"{v:4d}  {k}")
    for f in failures:
        print("FAILED", *f)
    shutil.rmtree(work, ignore_errors=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
