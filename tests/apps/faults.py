#!/usr/bin/env python3
"""Faults of the file system (issue 12): a disk that fills up at any point of any tool's writes, and an output
directory that is read-only. Needs root (it mounts small tmpfs file systems); as another user, or where mounting
is not allowed, it prints the reason and exits with 77, which ctest reports as skipped.

  disk_full      for each output of each tool (gen-configs dataset + config and label-mode CSV, train-net
                 network + config + C header and checkpoint, evaluate-net report directory and input-mode CSV)
                 the output directory is a tmpfs of sizes from one page to beyond the whole output: every run
                 ends with exit 0 and outputs byte-identical to a run on a roomy disk, or with exit 4 and
                 "No space left on device", the file system holding nothing new (no output, no temporary) and
                 an older output intact. Never a signal (the HDF5 close failure used to end in SIGSEGV).
  read_only      train-net with its output on a read-only file system fails before the first epoch (exit 4).

Usage: faults.py --gen-configs PATH --train-net PATH --evaluate-net PATH --source-dir DIR --work DIR [--case NAME]
"""
import argparse
import os
import re
import shutil
import subprocess
import sys

SKIP = 77
PAGE = 4096


class Failure(Exception):
    pass


def run(command, cwd, timeout=120):
    try:
        p = subprocess.run(command, cwd=cwd, capture_output=True, timeout=timeout)
    except subprocess.TimeoutExpired:
        raise Failure(f"hang: {' '.join(command)} ran past {timeout} s")
    return p.returncode, p.stderr.decode("utf-8", "replace")


def must(command, cwd):
    rc, err = run(command, cwd)
    if rc != 0:
        raise Failure(f"{' '.join(command)} failed ({rc}):\n{err}")


class Mount:
    """A tmpfs of `size` bytes (rounded up to pages) at `path`, read-only if asked; unmounted on exit."""

    def __init__(self, path, size, read_only=False):
        self.path = path
        self.options = f"size={size}" + (",ro" if read_only else "")

    def __enter__(self):
        os.makedirs(self.path, exist_ok=True)
        p = subprocess.run(["mount", "-t", "tmpfs", "-o", self.options, "tmpfs", self.path], capture_output=True)
        if p.returncode != 0:
            raise OSError(p.stderr.decode().strip())
        return self.path

    def __exit__(self, *_):
        subprocess.run(["umount", self.path], capture_output=True)


def contents(path):
    """Relative path -> bytes of every file under `path`."""
    result = {}
    for root, _, files in os.walk(path):
        for name in files:
            full = os.path.join(root, name)
            with open(full, "rb") as f:
                result[os.path.relpath(full, path)] = f.read()
    return result


def total_size(files):
    return sum(len(b) for b in files.values())


def comparable(rel):
    """Outputs that name the output path inside (effective configs, the report's command line) differ between
    directories; the others must be byte-identical."""
    return not rel.endswith(".config.toml") and os.path.basename(rel) != "report.md"


def disk_full_case(name, work, command, prepare=None, may_leave=None):
    """Runs `command(out_dir)` with out_dir a roomy directory (the reference), then on tmpfs of growing
    sizes, with and without an older complete output already there. `may_leave(name, data)`: a file a
    failed run may leave (a checkpoint written before the disk filled), checked by the callback."""
    ref_dir = os.path.join(work, name + "-reference")
    os.makedirs(ref_dir)
    if prepare:
        prepare(ref_dir)
    before_ref = contents(ref_dir)
    must(command(ref_dir), work)
    reference = {k: v for k, v in contents(ref_dir).items() if k not in before_ref}
    if not reference:
        raise Failure(f"{name}: the reference run wrote nothing")
    size = total_size(reference)
    mount_point = os.path.join(work, name + "-full")
    # tmpfs counts whole pages a file: the largest size holds every output file rounded up to pages (and a
    # spare page each), so that one run completes whatever the files' sizes (they vary with the path length).
    pages = sum(-(-len(data) // PAGE) + 1 for data in reference.values())
    sizes = sorted({PAGE * max(1, k) for k in range(1, pages + 1, max(1, pages // 14))} | {PAGE * pages})
    failed = completed = 0
    for limit in sizes:
        for keep_older in (False, True):
            try:
                with Mount(mount_point, limit):
                    if prepare:
                        prepare(mount_point)
                    older = {}
                    if keep_older:
                        # An older complete output, if it fits (it may not, on the smallest file systems).
                        try:
                            for rel, data in reference.items():
                                os.makedirs(os.path.dirname(os.path.join(mount_point, rel)), exist_ok=True)
                                with open(os.path.join(mount_point, rel), "wb") as f:
                                    f.write(data)
                            older = dict(reference)
                        except OSError:
                            shutil.rmtree(mount_point, ignore_errors=True)
                            os.makedirs(mount_point, exist_ok=True)
                            if prepare:
                                prepare(mount_point)
                            older = {}
                    before = contents(mount_point)
                    rc, err = run(command(mount_point), work)
                    after = contents(mount_point)
            except OSError as e:
                raise Failure(f"cannot mount a tmpfs: {e}")
            where = f"{name}, file system of {limit} bytes, older output {'kept' if older else 'absent'}"
            if rc < 0:
                raise Failure(f"{where}: killed by signal {-rc}\n{err}")
            if rc == 0:
                completed += 1
                for rel, data in reference.items():
                    if rel not in after or (comparable(rel) and after[rel] != data):
                        raise Failure(f"{where}: exit 0 but '{rel}' is missing or differs from the reference run's")
                extra = set(after) - set(before) - set(reference)
                if extra:
                    raise Failure(f"{where}: exit 0 and files left behind: {sorted(extra)}")
                continue
            failed += 1
            if rc != 4 or "No space left on device" not in err:
                raise Failure(f"{where}: exit {rc}, expected 0 or 4 with 'No space left on device':\n{err}")
            if "internal" in err or "[requirement" in err:
                raise Failure(f"{where}: internal error text:\n{err}")
            for rel in sorted(set(after) - set(before)):
                if may_leave is not None and may_leave(rel, after[rel]):
                    del after[rel]
            if after != before:
                added = sorted(set(after) - set(before))
                changed = sorted(k for k in before if k in after and after[k] != before[k])
                raise Failure(f"{where}: a failed run changed the file system: added {added}, changed {changed}")
    if failed == 0 or completed == 0:
        raise Failure(f"{name}: {failed} failed and {completed} completed runs; the sizes do not span the output")
    print(f"{name}: {len(sizes)} sizes x 2, output {size} bytes: {failed} runs failed cleanly (exit 4), "
          f"{completed} completed", flush=True)


def make_inputs(tools, source, work):
    inputs = os.path.join(work, "inputs")
    os.makedirs(inputs)
    with open(os.path.join(inputs, "grid.toml"), "w") as f:
        f.write("[gen-configs]\nd_xy_points = 6\nc_xy_points = 6\ns_xy_points = 8\nc_z_points = 3\ns_z_points = 3\n"
                "quiet = true\n")
    must([tools["gen-configs"], "--config", "grid.toml", "--output", "data.h5"], inputs)
    must([tools["train-net"], "--data", "data.h5", "--output", "net.h5", "--epochs", "5", "--train_count", "50",
          "--quiet"], inputs)
    shutil.copy(os.path.join(source, "data", "examples", "raw-bilinear.csv"), os.path.join(inputs, "raw.csv"))
    with open(os.path.join(inputs, "raw.csv")) as f:
        lines = f.read().splitlines()
    with open(os.path.join(inputs, "raw.csv"), "w") as f:  # a few hundred rows: several pages of output
        f.write("\n".join([lines[0]] + [l for _ in range(60) for l in lines[1:]]) + "\n")
    return inputs


def case_disk_full(tools, source, work):
    inputs = make_inputs(tools, source, work)
    i = lambda name: os.path.join(inputs, name)
    disk_full_case("gen-configs-dataset", work,
                   lambda d: [tools["gen-configs"], "--config", i("grid.toml"), "--output", os.path.join(d, "out.h5")])
    disk_full_case("gen-configs-labels", work,
                   lambda d: [tools["gen-configs"], "--input", i("raw.csv"), "--output", os.path.join(d, "out.csv")])
    train = [tools["train-net"], "--data", i("data.h5"), "--epochs", "6", "--train_count", "50", "--quiet",
             "--threads", "1", "--hidden", "24"]
    disk_full_case("train-net-network", work,
                   lambda d: train + ["--output", os.path.join(d, "net.h5"), "--export-header", os.path.join(d, "net.h")])
    resumed = os.path.join(work, "resumed")
    os.makedirs(resumed)

    def checkpoint_resumes(rel, data):
        """A checkpoint left by a run that failed later is whole: --resume from it (on a roomy disk) ends with
        the network of an uninterrupted run."""
        if rel != "net.h5.checkpoint.h5":
            return False
        with open(os.path.join(resumed, rel), "wb") as f:
            f.write(data)
        must(train + ["--output", os.path.join(resumed, "net.h5"), "--checkpoint-every", "3", "--resume"], work)
        with open(os.path.join(resumed, "net.h5"), "rb") as a, \
                open(os.path.join(work, "train-net-checkpoint-reference", "net.h5"), "rb") as b:
            if a.read() != b.read():
                raise Failure("a checkpoint left by a failed run does not resume to the uninterrupted network")
        return True

    disk_full_case("train-net-checkpoint", work,
                   lambda d: train + ["--output", os.path.join(d, "net.h5"), "--checkpoint-every", "3"],
                   may_leave=checkpoint_resumes)
    disk_full_case("evaluate-net-report", work,
                   lambda d: [tools["evaluate-net"], "--weights", i("net.h5"), "--data", i("data.h5"), "--report",
                              os.path.join(d, "rep"), "--timing", "false", "--quiet"])
    disk_full_case("evaluate-net-input", work,
                   lambda d: [tools["evaluate-net"], "--weights", i("net.h5"), "--input", i("raw.csv"), "--output",
                              os.path.join(d, "pred.csv")])


def case_read_only(tools, source, work):
    inputs = make_inputs(tools, source, work)
    mount_point = os.path.join(work, "read-only")
    try:
        with Mount(mount_point, 1 << 20, read_only=True):
            rc, err = run([tools["train-net"], "--data", os.path.join(inputs, "data.h5"), "--output",
                           os.path.join(mount_point, "net.h5"), "--epochs", "100000000", "--train_count", "50",
                           "--quiet"], work, timeout=60)
    except OSError as e:
        raise Failure(f"cannot mount a tmpfs: {e}")
    if rc != 4 or not re.search(r"^error: --output: cannot write '[^']*net\.h5': cannot create a file in directory '[^']*': "
                                r"Read-only file system\n$", err):
        raise Failure(f"train-net on a read-only directory: exit {rc}, expected 4 before the first epoch:\n{err}")
    print("read_only: train-net refused a read-only output directory before the first epoch", flush=True)


CASES = {"disk_full": case_disk_full, "read_only": case_read_only}


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--gen-configs", dest="gen_configs", required=True)
    parser.add_argument("--train-net", dest="train_net", required=True)
    parser.add_argument("--evaluate-net", dest="evaluate_net", required=True)
    parser.add_argument("--source-dir", required=True)
    parser.add_argument("--work", required=True)
    parser.add_argument("--case", action="append", default=[])
    a = parser.parse_args()
    tools = {"gen-configs": os.path.abspath(a.gen_configs), "train-net": os.path.abspath(a.train_net),
             "evaluate-net": os.path.abspath(a.evaluate_net)}
    if os.geteuid() != 0:
        print("SKIPPED: the fault cases mount small tmpfs file systems, which needs root", flush=True)
        return SKIP
    work = os.path.abspath(a.work)
    probe = os.path.join(work, "probe")
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(work)
    try:
        with Mount(probe, PAGE):
            pass
    except OSError as e:
        print(f"SKIPPED: cannot mount a tmpfs here ({e})", flush=True)
        return SKIP
    failed = 0
    for name in a.case or list(CASES):
        case_work = os.path.join(work, name)
        os.makedirs(case_work)
        try:
            CASES[name](tools, os.path.abspath(a.source_dir), case_work)
            print(f"PASS {name}", flush=True)
        except Failure as e:
            failed += 1
            print(f"FAIL {name}\n{e}", flush=True)
    if not failed:
        shutil.rmtree(work, ignore_errors=True)
    return 1 if failed else 0


if __name__ == "__main__":
    sys.exit(main())
