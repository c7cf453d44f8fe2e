"""Cases of scripts/faults.py (registered in fault_cases.CASES): damaged maps,
vocabularies and detections; signals, kills, full disks and closed streams; the
other commands."""
import os
import resource

import fault_files as files
from fault_cases import (BASE_FRAMES, SIG, STARTED, SkipCase, append, at_time, case, check_map, copy_eval_inputs,
                         edit, garbage, list_lines, replace_file, stats_of, when_exists, when_log, write_lines)


# --- maps, vocabulary, detections -----------------------------------------

def damaged_map(t, damage):
    _, saved = t.suite.reference()
    with open(saved, "rb") as f:
        data = f.read()
    replace_file(t.path("damaged.map"), damage(data))
    return t.path("damaged.map")


@case("load-map-truncated", "--load-map a map file cut to half its length", 1, r"damaged\.map", short=True)
def _(t):
    t.run(t.dataset(), "--load-map", damaged_map(t, lambda d: d[:len(d) // 2]))


@case("load-map-corrupt", "--load-map a map file with one byte changed in the middle", 1, r"damaged\.map")
def _(t):
    def flip(d):
        return d[:len(d) // 2] + bytes([d[len(d) // 2] ^ 0x40]) + d[len(d) // 2 + 1:]
    t.run(t.dataset(), "--load-map", damaged_map(t, flip))


@case("load-map-random", "--load-map 64 KiB of random bytes", 1, r"damaged\.map")
def _(t):
    t.run(t.dataset(), "--load-map", damaged_map(t, lambda d: garbage(65536)))


@case("load-map-empty", "--load-map an empty file", 1, r"damaged\.map")
def _(t):
    t.run(t.dataset(), "--load-map", damaged_map(t, lambda d: b""))


@case("load-map-other-camera", "--load-map a map made with fx 525 on a camera with fx 520", 1, r"camera|fx")
def _(t):
    ds = t.dataset()
    edit(os.path.join(ds, "sgslam.yaml"), r"^  fx: .*$", "  fx: 520.0")
    t.run(ds, "--load-map", damaged_map(t, lambda d: d))


@case("load-map-folder", "--load-map a folder", 2, r"--load-map")
def _(t):
    os.makedirs(t.path("map"))
    t.run(t.dataset(), "--load-map", t.path("map"))


def vocabulary_case(t, damage):
    shipped = t.suite.vocabulary()
    if shipped is None:
        raise SkipCase("skipped: no vocabulary beside the program")
    with open(shipped, "rb") as f:
        replace_file(t.path("bad.vocab"), damage(f.read()))
    ds = t.dataset()
    append(os.path.join(ds, "sgslam.yaml"), f"loop:\n  vocabulary: {t.path('bad.vocab')}\n")
    t.run(ds)


@case("vocabulary-corrupt", "loop.vocabulary: the shipped file with one byte changed", 1, r"bad\.vocab")
def _(t):
    vocabulary_case(t, lambda d: d[:len(d) // 3] + bytes([d[len(d) // 3] ^ 1]) + d[len(d) // 3 + 1:])


@case("vocabulary-truncated", "loop.vocabulary: the shipped file cut to 1000 bytes", 1, r"bad\.vocab")
def _(t):
    vocabulary_case(t, lambda d: d[:1000])


@case("detections-binary", "detections.txt (detector.backend: file) of random bytes", 1, r"detections\.txt:\d+")
def _(t):
    ds = t.dataset()
    replace_file(os.path.join(ds, "detections.txt"), garbage(4096, seed=11))
    t.run(ds)


@case("detections-missing", "detections.txt deleted (detector.backend: file)", 1, r"detections file not found")
def _(t):
    ds = t.dataset()
    os.remove(os.path.join(ds, "detections.txt"))
    t.run(ds)


def boxes_everywhere(t, ds, lines):
    stamps = [l.split()[0] for l in files.data_lines(os.path.join(ds, "rgb.txt"))]
    write_lines(os.path.join(ds, "detections.txt"), [f"{s} {line}" for s in stamps for line in lines])


@case("detections-huge-boxes", "a box of +-1e30 px in every frame's detections", 1,
      r"detections\.txt:\d+.*beyond", short=True)
def _(t):
    ds = t.dataset()
    boxes_everywhere(t, ds, ["0 1.0 -1e30 -1e30 1e30 1e30 person"])
    t.run(ds, "--max-frames", 12)


@case("detections-far-boxes", "boxes of +-1e5 px, far outside the image, and class 999999 in every frame", 0)
def _(t):
    ds = t.dataset()
    boxes_everywhere(t, ds, ["0 1.0 -1e5 -1e5 1e5 1e5 person", "999999 0.5 100 100 9e5 9e5 thing"])
    t.run(ds, "--max-frames", 12, frames=(12, 12))


# --- signals, kills and stops ---------------------------------------------

@case("save-map-sigterm", "SIGTERM during a run with --save-map", 143, r"interrupted by SIGTERM")
def _(t):
    saved = t.path("saved.map")
    t.writable.add(saved)
    t.run(t.dataset(), "--realtime", "--save-map", saved, frames=(1, BASE_FRAMES - 1),
          driver=when_log(STARTED, 0.6, SIG.SIGTERM))
    check_map(t, saved)


@case("save-map-folder", "--save-map an existing folder", 1, r"--save-map .* is a folder")
def _(t):
    os.makedirs(t.path("m.map"))
    t.run(t.dataset(), "--save-map", t.path("m.map"))


@case("sigusr1-twice", "two SIGUSR1 30 ms apart with --save-map (live map and OctoMap)", 0)
def _(t):
    saved = t.path("saved.map")
    t.writable.add(saved)
    t.run(t.dataset(), "--realtime", "--every-frame", "--save-map", saved, frames=(BASE_FRAMES, BASE_FRAMES),
          driver=when_log(STARTED, 0.5, SIG.SIGUSR1, SIG.SIGUSR1, gap=0.03))
    check_map(t, saved)


@case("sigusr1-then-sigterm", "SIGUSR1 (a live map save) and SIGTERM 10 ms later", 143, r"interrupted by SIGTERM")
def _(t):
    saved = t.path("saved.map")
    t.writable.add(saved)
    t.run(t.dataset(), "--realtime", "--save-map", saved, frames=(1, BASE_FRAMES - 1),
          driver=when_log(STARTED, 0.5, SIG.SIGUSR1, SIG.SIGTERM, gap=0.01))
    check_map(t, saved)


@case("sigint-twice", "Ctrl-C twice, 50 ms apart", 130, r"interrupted by SIGINT")
def _(t):
    t.run(t.dataset(), "--realtime", frames=(1, BASE_FRAMES - 1),
          driver=when_log(STARTED, 0.5, SIG.SIGINT, SIG.SIGINT))


@case("sigkill-mid-run", "SIGKILL 0.5 s into a run: what is there is whole, no temporary file left", -9)
def _(t):
    t.run(t.dataset(), "--realtime", driver=when_log(STARTED, 0.5, SIG.SIGKILL))


@case("sigkill-while-writing", "SIGKILL as soon as trajectory.txt appears (outputs being written): "
      "no temporary file left (outputs are written unnamed, O_TMPFILE)", (-9, 0), short=True)
def _(t):
    t.run(t.dataset(), "--max-frames", 20, driver=when_exists(t.path("out", "trajectory.txt"), SIG.SIGKILL))


@case("sigterm-while-writing", "SIGTERM as soon as frames.csv appears (outputs being written)", (0, 143))
def _(t):
    t.run(t.dataset(), "--max-frames", 20, frames=(20, 20),
          driver=when_exists(t.path("out", "frames.csv"), SIG.SIGTERM))


@case("sigterm-at-start", "SIGTERM 20 ms after the start (before the handlers or during start-up)", (143, -15))
def _(t):
    t.run(t.dataset(), frames=(1, BASE_FRAMES - 1), driver=at_time(0.02, SIG.SIGTERM))


@case("sigterm-during-startup", "SIGTERM as the dataset is read, before the system and vocabulary are up", 143,
      r"interrupted by SIGTERM")
def _(t):
    t.run(t.dataset(), frames=(1, 3), driver=when_log(r"RGB-D frames", 0.0, SIG.SIGTERM))


def shift_timestamps(path, first, seconds):
    """Every listed frame from the first-th on an hour (seconds) later."""
    lines, n = list_lines(path), 0
    for k, line in enumerate(lines):
        if line.startswith("#"):
            continue
        if n >= first:
            stamp, rest = line.split(" ", 1)
            lines[k] = f"{float(stamp) + seconds:.6f} {rest}"
        n += 1
    write_lines(path, lines)


@case("realtime-gap-sigterm", "SIGTERM while --realtime waits for a frame stamped an hour after the one before",
      143, r"interrupted by SIGTERM", short=True, timeout=30)
def _(t):
    ds = t.dataset()
    for name in ("rgb.txt", "depth.txt"):
        shift_timestamps(os.path.join(ds, name), 10, 3600.0)
    t.run(ds, "--realtime", "--max-frames", 12, frames=(1, 11), driver=when_log(STARTED, 1.0, SIG.SIGTERM))


@case("stats-is-folder", "stats.json a folder in the output folder", 1, r"outputs not written: stats\.json")
def _(t):
    os.makedirs(t.path("out", "stats.json"))
    t.run(t.dataset(), "--max-frames", 8)
    for name in ("trajectory.txt", "frames.csv", "cloud.ply"):
        if not os.path.isfile(t.path("out", name)):
            t.problem("lost", f"{name} not written")


@case("config-used-is-folder", "config_used.yaml a folder in the output folder (written before the first frame)",
      1, r"config_used\.yaml")
def _(t):
    os.makedirs(t.path("out", "config_used.yaml"))
    t.run(t.dataset(), "--max-frames", 8)


@case("out-is-dataset", "--out the dataset folder itself", 1, r"is the dataset folder")
def _(t):
    ds = t.dataset()
    inputs = ("rgb.txt", "depth.txt", "groundtruth.txt", "sgslam.yaml", "mask.txt", "detections.txt")
    before = {n: open(os.path.join(ds, n), "rb").read() for n in inputs}
    t.writable.add(ds)
    t.sgslam("run", "--dataset", ds, "--out", ds, "--max-frames", 8)
    changed = [n for n in inputs if open(os.path.join(ds, n), "rb").read() != before[n]]
    if changed:
        t.problem("inputs", "inputs replaced by outputs of the same name: " + ", ".join(changed))


@case("disk-full", "file size limit of 150 KB, writes past it failing (EFBIG, as a full disk)", 1,
      r"outputs not written: .*cloud\.ply", short=True)
def _(t):
    # Sequential: the cloud's size (285 KB) does not depend on the semantic thread keeping up.
    t.run(t.dataset(), "--max-frames", 20, "--sequential", frames=(20, 20),
          limits=[(resource.RLIMIT_FSIZE, 150_000)])
    failed = stats_of(t).get("failed_outputs", [])
    for small in ("objects.json", "trajectory.txt"):
        if small in failed or not os.path.isfile(t.path("out", small)):
            t.problem("lost", f"{small} (a few KB) not written beside the outputs that did not fit")


@case("mcap-disk-full", "--mcap with the file size limit of 150 KB (as a full disk): the recording stops, "
      "the run and its other outputs go on", 1, r"outputs not written: .*--mcap", short=True)
def _(t):
    t.writable.update({t.path("rec.mcap"), t.path("rec.mcap.part")})
    t.run(t.dataset(), "--max-frames", 20, "--sequential", "--mcap", t.path("rec.mcap"), frames=(20, 20),
          limits=[(resource.RLIMIT_FSIZE, 150_000)])
    if os.path.exists(t.path("rec.mcap")) or not os.path.isfile(t.path("rec.mcap.part")):
        t.problem("lost", "the recording that did not fit is not kept as rec.mcap.part (or was named rec.mcap)")
    for small in ("objects.json", "trajectory.txt"):
        if not os.path.isfile(t.path("out", small)):
            t.problem("lost", f"{small} not written beside the recording that did not fit")


@case("mcap-sigint", "Ctrl-C during a run with --mcap: the recording is finished (summary, footer)", 130,
      r"interrupted by SIGINT")
def _(t):
    rec = t.path("rec.mcap")
    t.writable.add(rec)
    t.run(t.dataset(), "--realtime", "--mcap", rec, frames=(1, BASE_FRAMES - 1),
          driver=when_log(STARTED, 0.5, SIG.SIGINT))
    with open(rec, "rb") as f:
        data = f.read()
    magic = b"\x89MCAP0\r\n"
    # The footer (opcode 2, length 20) just before the closing magic.
    if not (data.startswith(magic) and data.endswith(magic) and data[-37] == 2):
        t.problem("lost", "the recording is not finished: no footer and closing magic")


@case("stdin-closed", "standard input closed", 0)
def _(t):
    t.run(t.dataset(), "--max-frames", 8, frames=(8, 8), close_fds=(0,))


@case("stdout-stderr-closed", "standard output and error closed (file descriptors 1 and 2 free)", 0, short=True)
def _(t):
    t.run(t.dataset(), "--max-frames", 20, "--save-map", t.path("out", "m.map"), frames=(20, 20), close_fds=(1, 2))


@case("eval-stdout-full", "eval --json with standard output on /dev/full", 1, r"standard output", short=True)
def _(t):
    gt, est = copy_eval_inputs(t)
    t.sgslam("eval", "--gt", gt, "--est", est, "--json", stdout_path="/dev/full")


@case("run-stdout-full", "run with standard output on /dev/full (the summary line lost)", 1, r"standard output")
def _(t):
    t.run(t.dataset(), "--max-frames", 5, frames=(5, 5), stdout_path="/dev/full", ended="completed")


# --- other commands -------------------------------------------------------

@case("eval-gt-nan", "eval --gt with 'nan' for x in its first pose", 1, r"groundtruth\.txt:\d+")
def _(t):
    gt, est = copy_eval_inputs(t)
    edit(gt, r"^(\d\S*) \S+", r"\1 nan")
    t.sgslam("eval", "--gt", gt, "--est", est)


@case("eval-est-empty", "eval --est an empty file", 1, r"trajectory\.txt")
def _(t):
    gt, est = copy_eval_inputs(t)
    replace_file(est, b"")
    t.sgslam("eval", "--gt", gt, "--est", est)


@case("eval-est-list", "eval --est an image list (2 fields a line)", 1, r"rgb\.txt:\d+")
def _(t):
    gt, _ = copy_eval_inputs(t)
    with open(os.path.join(t.suite.base, "rgb.txt"), "rb") as f:
        replace_file(t.path("rgb.txt"), f.read())
    t.sgslam("eval", "--gt", gt, "--est", t.path("rgb.txt"))


@case("eval-plot-is-folder", "eval --plot an existing folder", 1, r"ate\.png", short=True)
def _(t):
    gt, est = copy_eval_inputs(t)
    os.makedirs(t.path("plots", "ate.png"))
    t.writable.add(t.path("plots"))
    t.sgslam("eval", "--gt", gt, "--est", est, "--plot", t.path("plots", "ate.png"))
    left = [n for n in os.listdir(t.path("plots")) if n != "ate.png"]
    if left:
        t.problem("lost", f"left in plots/: {left}")


@case("synth-out-not-empty", "synth --out a folder holding a file", 1, r"empty")
def _(t):
    os.makedirs(t.path("s"))
    replace_file(t.path("s", "keep.txt"), b"keep\n")
    t.sgslam("synth", "--frames", 3, "--out", t.path("s"))


@case("synth-frames-negative", "synth --frames -3", (1, 2), r"frames")
def _(t):
    t.writable.add(t.path("s"))
    t.sgslam("synth", "--frames", "-3", "--out", t.path("s"))


@case("map-info-random", "map info on 4 KiB of random bytes", 1, r"junk\.map")
def _(t):
    replace_file(t.path("junk.map"), garbage(4096))
    t.sgslam("map", "info", t.path("junk.map"))


@case("vocab-info-truncated", "vocab info on the shipped vocabulary cut to half", 1, r"half\.vocab")
def _(t):
    shipped = t.suite.vocabulary()
    if shipped is None:
        raise SkipCase("skipped: no vocabulary beside the program")
    with open(shipped, "rb") as f:
        data = f.read()
    replace_file(t.path("half.vocab"), data[:len(data) // 2])
    t.sgslam("vocab", "info", t.path("half.vocab"))
