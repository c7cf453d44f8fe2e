#!/usr/bin/env python3
"""Fault-injection suite for sgslam (issue #37): no crash on any input, no output
lost on any stop, no write outside the output folder.

  scripts/faults.py [--sgslam build/sgslam] [--short] [--only REGEX] [--markdown FILE]

Renders a short synthetic sequence once (`sgslam synth`) into a temporary folder,
then runs each case on a copy it damages: a bad config, a damaged image or list, a
signal at some moment, an output that cannot be written. Each case has an expected
exit status and a pattern its messages must match; every case is also checked for
a crash (death by a signal not sent, a sanitizer report), a hang (its time bound),
outputs missing, cut short or inconsistent with stats.json, temporary files left
behind, and anything written outside the output folder. The cases are in
scripts/fault_cases*.py; the results of the last full run are in docs/reliability.md.
--short runs the subset CI runs (under a minute). Exit status 1 when a case fails.
"""
import argparse
import json
import os
import re
import shutil
import signal
import subprocess
import sys
import tempfile
import time

import fault_files as files
from fault_cases import BASE_FRAMES, SkipCase

SANITIZER = re.compile(r"AddressSanitizer|LeakSanitizer|ThreadSanitizer|UndefinedBehaviorSanitizer|"
                       r"runtime error:|terminate called|Segmentation fault|core dumped")
BASE_OUTPUTS = ["trajectory.txt", "trajectory_online.txt", "keyframes.txt", "frames.csv", "stats.json",
                "config_used.yaml", "map_points.ply"]
SEMANTIC_OUTPUTS = ["cloud.ply", "octomap.bt", "objects.json", "map_top.png"]


class Proc:
    """One finished (or killed) process: exit status or signal, output, time, memory."""

    def __init__(self):
        self.status = None  # exit status, when it exited
        self.signal = None  # the signal that ended it
        self.timed_out = False
        self.out = self.err = ""
        self.seconds = 0.0
        self.max_rss_mib = 0.0
        self.sent = []  # the signals the case sent

    def describe(self):
        if self.timed_out:
            return "hang"
        if self.signal is not None:
            return signal.Signals(self.signal).name
        return str(self.status)


class Watch:
    """What a driver (a function called every few ms while the process runs) sees."""

    def __init__(self, popen, err_path, started, proc):
        self.popen, self.err_path, self.started, self.proc = popen, err_path, started, proc

    @property
    def elapsed(self):
        return time.monotonic() - self.started

    def stderr(self):
        with open(self.err_path, encoding="utf-8", errors="replace") as f:
            return f.read()

    def kill(self, sig):
        self.proc.sent.append(sig)
        os.kill(self.popen.pid, sig)


def child_setup(close_fds, limits):
    def setup():
        import resource
        resource.setrlimit(resource.RLIMIT_CORE, (0, 0))
        for what, value in limits:
            resource.setrlimit(what, (value, value))
            if what == resource.RLIMIT_FSIZE:
                signal.signal(signal.SIGXFSZ, signal.SIG_IGN)  # writes fail with EFBIG, as on a full disk
        for fd in close_fds:
            os.close(fd)
    return setup


def run_process(argv, cwd, timeout, driver=None, close_fds=(), limits=(), stdout_path=None):
    """Runs argv with a time bound; the driver may send signals meanwhile. Peak RSS
    is this child's own (wait4)."""
    proc = Proc()
    out_path = stdout_path or os.path.join(cwd, ".stdout")
    err_path = os.path.join(cwd, ".stderr")
    started = time.monotonic()
    with open(out_path, "wb") as out, open(err_path, "wb") as err:
        popen = subprocess.Popen(argv, cwd=cwd, stdin=subprocess.DEVNULL, stdout=out, stderr=err,
                                 start_new_session=True, preexec_fn=child_setup(close_fds, limits))
    watch = Watch(popen, err_path, started, proc)
    while True:
        pid, status, usage = os.wait4(popen.pid, os.WNOHANG)
        if pid:
            break
        if watch.elapsed > timeout:
            proc.timed_out = True
            os.killpg(popen.pid, signal.SIGKILL)
            pid, status, usage = os.wait4(popen.pid, 0)
            break
        if driver:
            driver(watch)
        time.sleep(0.005)
    popen.returncode = 0  # reaped here, by wait4
    proc.seconds = watch.elapsed
    proc.max_rss_mib = usage.ru_maxrss / 1024.0
    if os.WIFSIGNALED(status):
        proc.signal = os.WTERMSIG(status)
    else:
        proc.status = os.WEXITSTATUS(status)
    if stdout_path is None:
        with open(out_path, encoding="utf-8", errors="replace") as f:
            proc.out = f.read()
    proc.err = watch.stderr()
    return proc


def snapshot(root, skip):
    """Every entry under root (not following links) but those under skip: size,
    mtime and link target, to tell whether a run wrote where it should not."""
    seen = {}
    for folder, dirs, names in os.walk(root):
        dirs[:] = [d for d in dirs if os.path.join(folder, d) not in skip]
        for name in dirs + names:
            path = os.path.join(folder, name)
            if path in skip or name in (".stdout", ".stderr"):
                continue
            st = os.lstat(path)
            link = os.readlink(path) if os.path.islink(path) else None
            seen[os.path.relpath(path, root)] = (st.st_size, st.st_mtime_ns, st.st_mode, link)
    return seen


class Suite:
    """The shared inputs: the binary, the rendered sequence, a saved map."""

    def __init__(self, sgslam, work, timeout_scale, rss_limit_mib):
        self.sgslam, self.work, self.timeout_scale = sgslam, work, timeout_scale
        self.rss_limit_mib = rss_limit_mib  # the huge-image cases' bound on peak memory
        self._map = None
        self._reference = None
        self.base = os.path.join(work, "base")
        proc = run_process([sgslam, "synth", "--preset", "walkers", "--frames", str(BASE_FRAMES), "--out", self.base],
                           work, 300 * timeout_scale)
        if proc.status != 0:
            raise SystemExit(f"faults: sgslam synth failed ({proc.describe()}):\n{proc.err}")
        os.remove(os.path.join(self.base, "associations.txt"))  # rgb.txt and depth.txt are read
        self.rgb = [l.split()[1] for l in files.data_lines(os.path.join(self.base, "rgb.txt"))]
        self.depth = [l.split()[1] for l in files.data_lines(os.path.join(self.base, "depth.txt"))]

    def reference(self):
        """A finished run of 20 frames with its map saved: (out folder, map file)."""
        if self._reference is None:
            out, saved = os.path.join(self.work, "ref-out"), os.path.join(self.work, "ref.map")
            proc = run_process([self.sgslam, "-q", "run", "--dataset", self.base, "--out", out, "--max-frames", "20",
                                "--sequential", "--save-map", saved], self.work, 300 * self.timeout_scale)
            if proc.status != 0:
                raise SystemExit(f"faults: the reference run failed ({proc.describe()}):\n{proc.err}")
            self._reference = (out, saved)
        return self._reference

    def vocabulary(self):
        path = os.path.join(os.path.dirname(self.sgslam), "share", "sgslam", "vocabulary", "orb-k10-l5.vocab")
        return path if os.path.isfile(path) else None


class Trial:
    """One case being run: its folder, its processes and the problems found."""

    def __init__(self, suite, case, folder):
        self.suite, self.case, self.dir = suite, case, folder
        self.proc = None  # the process whose exit status the case expects
        self.problems = []  # (kind, text); kind: crash, hang, lost, torn, outside, status, message, other
        self.notes = []
        self.writable = set()  # paths a run may write besides its output folder
        self.messages = []  # patterns the output must match, besides the case's own

    def path(self, *parts):
        return os.path.join(self.dir, *parts)

    def problem(self, kind, text):
        self.problems.append((kind, text))

    def dataset(self, name="seq"):
        """A fresh copy of the rendered sequence: its images hard links (replace,
        never edit, one: replace_file), its lists and configs copies."""
        dst = self.path(name)
        for folder, _, names in os.walk(self.suite.base):
            rel = os.path.relpath(folder, self.suite.base)
            os.makedirs(os.path.join(dst, rel), exist_ok=True)
            for n in names:
                src, to = os.path.join(folder, n), os.path.join(dst, rel, n)
                if rel == ".":
                    shutil.copy2(src, to)
                else:
                    os.link(src, to)
        return dst

    def sgslam(self, *args, driver=None, timeout=None, close_fds=(), limits=(), stdout_path=None, main=True):
        """Runs sgslam with args in the case's folder; checks that nothing outside the
        writable paths changed and that it neither crashed nor hung."""
        before = snapshot(self.dir, self.writable)
        limit = (timeout or self.case.timeout) * self.suite.timeout_scale
        proc = run_process([self.suite.sgslam, *map(str, args)], self.dir, limit, driver, close_fds, limits,
                           stdout_path)
        if main:
            self.proc = proc
        after = snapshot(self.dir, self.writable)
        changed = sorted(k for k in set(before) | set(after) if before.get(k) != after.get(k))
        if changed:
            self.problem("outside", "written outside the output folder: " + ", ".join(changed[:5]))
        if proc.timed_out:
            self.problem("hang", f"no exit within {limit:.0f} s")
        elif proc.signal is not None and proc.signal not in proc.sent:
            self.problem("crash", f"died of {proc.describe()}")
        if SANITIZER.search(proc.err):
            self.problem("crash", "crash or sanitizer report: " + SANITIZER.search(proc.err).group(0))
        return proc

    def run(self, dataset, *args, out="out", frames=None, allow_tmp=False, planted=(), ended=None, **kw):
        """sgslam run on dataset into out, then the checks of its outputs (ended:
        what stats.json must say, when not what the exit status implies)."""
        out = self.path(out)
        self.writable.add(out)
        proc = self.sgslam("run", "--dataset", dataset, "--out", out, *args, **kw)
        check_run_outputs(self, out, proc, frames, allow_tmp, planted, ended)
        return proc


def check_run_outputs(trial, out, proc, frames, allow_tmp, planted, ended):
    """Every file in out whole; no temporary file left; when stats.json says frames
    were processed, every output there, and the counts agree with it."""
    names = sorted(os.listdir(out)) if os.path.isdir(out) else []
    tmp = [n for n in names if ".tmp" in n and n not in planted]
    if tmp and not allow_tmp:
        trial.problem("lost", "temporary files left: " + ", ".join(tmp))
    elif tmp:
        trial.notes.append(f"{len(tmp)} temporary file(s) left by the kill")
    for n in names:
        problem = files.check_output_file(os.path.join(out, n))
        if problem:
            trial.problem("torn", f"{n}: {problem}")
    stats = load_stats(trial, out)
    if stats is None:
        if frames and frames[0] > 0 and (proc.signal is None or proc.signal not in proc.sent):
            trial.problem("lost", "stats.json missing")
        return
    if frames is not None and not (frames[0] <= stats.get("frames", -1) <= frames[1]):
        trial.problem("other", f"stats.json says {stats.get('frames')} frames, expected {frames[0]}..{frames[1]}")
    if ended is None:
        check_ended(trial, stats, proc)
    elif stats.get("ended") != ended:
        trial.problem("other", f"stats.json ended '{stats.get('ended')}', expected '{ended}'")
    if stats.get("frames", 0) > 0:
        check_outputs_present(trial, out, stats, names)
        check_counts(trial, out, stats)


def load_stats(trial, out):
    path = os.path.join(out, "stats.json")
    if not os.path.isfile(path):
        return None
    try:
        with open(path, encoding="utf-8") as f:
            stats = json.load(f)
    except ValueError:
        return None  # reported as torn
    if "ended" not in stats or "frames" not in stats:
        trial.problem("other", "stats.json without 'ended' or 'frames'")
    return stats


def check_ended(trial, stats, proc):
    ended = str(stats.get("ended", ""))
    if proc.status == 0:
        ok = ended == "completed"
    elif proc.status is not None and proc.status > 128:
        ok = ended == "interrupted by " + signal.Signals(proc.status - 128).name
    elif proc.status == 1:
        ok = ended.startswith("failed: ") or bool(stats.get("failed_outputs")) or "map_file" in stats
    else:
        ok = proc.signal is not None
    if not ok:
        trial.problem("other", f"stats.json ended '{ended}' does not match exit {proc.describe()}")


def check_outputs_present(trial, out, stats, names):
    failed = set(stats.get("failed_outputs", []))
    expected = list(BASE_OUTPUTS)
    if semantic_enabled(os.path.join(out, "config_used.yaml")) and "the semantic map" not in failed:
        expected += SEMANTIC_OUTPUTS
    if stats.get("mode") in ("sg", "semantic") and not str(stats["dynamic"]["detector"]).startswith("none"):
        expected.append("detections.txt")
    missing = [n for n in expected if n not in names and n not in failed]
    if missing:
        trial.problem("lost", "outputs missing: " + ", ".join(missing))


def semantic_enabled(config_used):
    try:
        with open(config_used, encoding="utf-8") as f:
            text = f.read()
    except OSError:
        return True
    section = re.search(r"^semantic:\n((?:[ #].*\n)*)", text, re.M)
    return not (section and re.search(r"^\s+enabled: false", section.group(1), re.M))


def check_counts(trial, out, stats):
    def rows(name, header=0):
        path = os.path.join(out, name)
        return len(files.data_lines(path)) - header if os.path.isfile(path) else None
    wanted = [("trajectory.txt", rows("trajectory.txt"), stats.get("tracked")),
              ("trajectory_online.txt", rows("trajectory_online.txt"), stats.get("tracked")),
              ("frames.csv", rows("frames.csv", header=1), stats.get("frames"))]
    ply = os.path.join(out, "map_points.ply")
    if os.path.isfile(ply) and files.check_ply(ply) is None:
        wanted.append(("map_points.ply", files.ply_vertices(ply), stats.get("map_points")))
    for name, got, want in wanted:
        if got is not None and got != want:
            trial.problem("lost", f"{name} has {got} rows, stats.json says {want}")


def judge(case, trial):
    """PASS, FAIL, XFAIL (an expected failure), XPASS or SKIP, and the reasons."""
    if trial.proc is None:
        return "SKIP", "; ".join(trial.notes)
    proc, problems = trial.proc, list(trial.problems)
    got = -proc.signal if proc.signal is not None else proc.status
    if not proc.timed_out and got not in case.exit:
        problems.append(("status", f"exit {proc.describe()}, expected {case.expected_text()}"))
    for pattern in filter(None, [case.message] + trial.messages):
        if not re.search(pattern, proc.out + proc.err, re.S | re.I):
            problems.append(("message", f"no message matching /{pattern}/"))
    text = "; ".join(t for _, t in problems)
    if case.xfail and not {"crash", "hang"} & {k for k, _ in problems}:
        return ("XFAIL" if problems else "XPASS"), "; ".join(filter(None, [text, case.xfail]))
    return ("FAIL" if problems else "PASS"), "; ".join(filter(None, [text] + trial.notes))


def run_case(suite, case, work):
    folder = os.path.join(work, case.name)
    os.makedirs(folder)
    trial = Trial(suite, case, folder)
    started = time.monotonic()
    try:
        case.fn(trial)
    except SkipCase as e:
        trial.proc = None
        trial.notes.append(str(e))
    except Exception as e:  # a broken case, not a finding about sgslam
        trial.problem("other", f"the case itself failed: {type(e).__name__}: {e}")
        if trial.proc is None:
            trial.proc = Proc()
    result, why = judge(case, trial)
    kinds = {k for k, _ in trial.problems}
    return {"case": case.name, "injected": case.injected, "expected": case.expected_text(),
            "got": trial.proc.describe() if trial.proc else "-", "result": result, "why": why,
            "kinds": sorted(kinds), "seconds": time.monotonic() - started, "short": case.short}


def print_table(rows):
    width = max(len(r["case"]) for r in rows)
    print(f"{'case':<{width}}  {'expected':>8}  {'got':>7}  {'result':<6}  {'s':>5}  injected / notes")
    for r in rows:
        print(f"{r['case']:<{width}}  {r['expected']:>8}  {r['got']:>7}  {r['result']:<6}  {r['seconds']:5.1f}  "
              f"{r['injected']}" + (f"\n{'':<{width}}  -> {r['why']}" if r["why"] else ""))


def summary(rows):
    count = {k: sum(1 for r in rows if r["result"] == k) for k in ("PASS", "FAIL", "XFAIL", "XPASS", "SKIP")}
    bad = [r for r in rows if r["result"] == "FAIL"]
    kinds = {k: sum(1 for r in bad if k in r["kinds"]) for k in ("crash", "hang", "lost", "torn", "outside")}
    return (f"{len(rows)} cases: {count['PASS']} passed, {count['FAIL']} failed, {count['XFAIL']} expected "
            f"failures, {count['XPASS']} unexpected passes, {count['SKIP']} skipped; crashes {kinds['crash']}, "
            f"hangs {kinds['hang']}, lost outputs {kinds['lost']}, torn outputs {kinds['torn']}, "
            f"writes outside {kinds['outside']}")


def write_markdown(path, rows, command, seconds):
    def cell(s):
        return str(s).replace("|", "\\|").replace("\n", " ")
    lines = [f"Command: `{command}` ({seconds:.0f} s).", "", summary(rows) + ".", "",
             "| case | injected | expected | got | result | notes |", "|---|---|---|---|---|---|"]
    for r in rows:
        name = r["case"] + (" (short)" if r["short"] else "")
        lines.append(f"| {name} | {cell(r['injected'])} | {r['expected']} | {r['got']} | {r['result']} | "
                     f"{cell(r['why'])} |")
    with open(path, "w", encoding="utf-8") as f:
        f.write("\n".join(lines) + "\n")


def main():
    import fault_cases
    import fault_cases_inputs  # noqa: F401 (registers its cases)
    import fault_cases_stops  # noqa: F401
    import fault_cases_paths  # noqa: F401
    import fault_cases_readers  # noqa: F401
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    here = os.path.dirname(os.path.abspath(__file__))
    p.add_argument("--sgslam", default=os.path.join(here, "..", "build", "sgslam"), help="the program to test")
    p.add_argument("--short", action="store_true", help="only the cases CI runs (under a minute)")
    p.add_argument("--only", help="only the cases whose name matches this regular expression")
    p.add_argument("--markdown", help="also write the results table to this Markdown file")
    p.add_argument("--timeout-scale", type=float, default=1.0, help="multiply every time bound (sanitizer builds)")
    p.add_argument("--rss-limit", type=float, default=600, metavar="MIB",
                   help="peak memory allowed where an image claims 900 MB (raise it for sanitizer builds)")
    p.add_argument("--keep", action="store_true", help="keep the temporary folder")
    a = p.parse_args()
    sgslam = os.path.abspath(a.sgslam)
    if not os.access(sgslam, os.X_OK):
        raise SystemExit(f"faults: no sgslam program at {sgslam} (build it, or pass --sgslam)")
    cases = [c for c in fault_cases.CASES if (not a.short or c.short) and (not a.only or re.search(a.only, c.name))]
    if not cases:
        raise SystemExit("faults: no case selected")
    work = tempfile.mkdtemp(prefix="sgslam-faults-")
    started = time.monotonic()
    try:
        suite = Suite(sgslam, work, a.timeout_scale, a.rss_limit)
        rows = []
        for c in cases:
            rows.append(run_case(suite, c, os.path.join(work, "cases")))
            r = rows[-1]
            print(f"{r['result']:<5} {r['case']} ({r['got']}, {r['seconds']:.1f} s)", flush=True)
    finally:
        if a.keep:
            print(f"faults: kept {work}")
        else:
            shutil.rmtree(work, ignore_errors=True)
    seconds = time.monotonic() - started
    print()
    print_table(rows)
    print(f"\n{summary(rows)} in {seconds:.0f} s")
    if a.markdown:
        command = "scripts/faults.py" + (" --short" if a.short else "") + (f" --only '{a.only}'" if a.only else "")
        write_markdown(a.markdown, rows, command, seconds)
    return 1 if any(r["result"] == "FAIL" for r in rows) else 0


if __name__ == "__main__":
    sys.exit(main())
