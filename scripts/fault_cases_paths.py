"""Cases of scripts/faults.py (issue #47): the paths the program writes: never the dataset, a file in use, another output or a system folder; temporary files a killed run left."""
import os
import re

import fault_files as files
from fault_cases import BASE_FRAMES, SIG, SkipCase, case, edit, append, replace_file, garbage, stats_of
import shutil
import stat
import subprocess
import sys

from fault_cases import check_map, copy_eval_inputs, when_exists

NOT_WRITTEN = "must stay as it is\n"


def keep(t, *parts):
    """A file of the case's folder with known content, checked unchanged by keep_checked."""
    path = t.path(*parts)
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path, "w", encoding="utf-8") as f:
        f.write(NOT_WRITTEN)
    return path


def unchanged(t, path, what):
    with open(path, encoding="utf-8", errors="replace") as f:
        if f.read() != NOT_WRITTEN:
            t.problem("outside", f"{what} was overwritten")


def dead_pid():
    """The id of a process that has ended."""
    child = subprocess.Popen([sys.executable, "-c", "pass"])
    child.wait()
    return child.pid


def write_config(t, text):
    path = t.path("c.yaml")
    with open(path, "w", encoding="utf-8") as f:
        f.write(text)
    return path


def temp_name(path, pid, suffix):
    """The temporary name a writer of path with process id pid gives (io/atomic_write.h):
    <path>.tmp-sgslam.<boot id's first 8>-<PID namespace in hex>.<pid>.<suffix>."""
    with open("/proc/sys/kernel/random/boot_id", encoding="ascii") as f:
        boot = f.read().strip()[:8]
    owner = f"{boot}-{os.stat('/proc/self/ns/pid').st_ino:x}"
    return f"{path}.tmp-sgslam.{owner}.{pid}.{suffix}"


def absent_after(t, folder, names):
    """Files that must not appear in a folder outside the case's own (a system folder)."""
    found = [n for n in names if os.path.lexists(os.path.join(folder, n))]
    for n in found:  # a regression: clean up what it wrote, and say so
        try:
            os.remove(os.path.join(folder, n))
        except OSError:
            pass
    if found:
        t.problem("outside", f"written into {folder}: " + ", ".join(found))


RUN_NAMES = ["trajectory.txt", "stats.json", "config_used.yaml", "frames.csv"]


# --- --save-map ------------------------------------------------------------

@case("save-map-dataset-list", "--save-map the dataset's rgb.txt (#47: associations.txt was replaced, rc 0)", 1,
      r"--save-map .*rgb\.txt: would be written into the dataset folder", short=True)
def _(t):
    ds = t.dataset()
    with open(os.path.join(t.suite.base, "rgb.txt"), encoding="utf-8") as f:
        rgb = f.read()
    t.run(ds, "--save-map", os.path.join(ds, "rgb.txt"))
    with open(os.path.join(ds, "rgb.txt"), encoding="utf-8") as f:
        if f.read() != rgb:
            t.problem("outside", "the dataset's rgb.txt changed")


@case("save-map-config", "--config c.yaml --save-map c.yaml (#47: the config became a map)", 1,
      r"--save-map .*c\.yaml is the configuration file given with --config")
def _(t):
    ds = t.dataset()
    config = t.path("c.yaml")
    with open(config, "w", encoding="utf-8") as f:
        f.write("orb: {features: 900}\n")
    t.run(ds, "--config", config, "--save-map", config)
    with open(config, encoding="utf-8") as f:
        if f.read() != "orb: {features: 900}\n":
            t.problem("outside", "the configuration file changed")


@case("save-map-config-link", "--save-map a link to the --config file", 1,
      r"is the configuration file given with --config")
def _(t):
    ds = t.dataset()
    config = keep(t, "c.yaml")
    with open(config, "w", encoding="utf-8") as f:
        f.write("orb: {features: 900}\n")
    os.symlink(config, t.path("link.map"))
    t.run(ds, "--config", t.path("link.map"), "--save-map", config)


@case("save-map-is-output", "--save-map OUT/trajectory.txt (#47: the map was logged saved, then overwritten)", 1,
      r"--save-map .*trajectory\.txt is also the run's trajectory\.txt")
def _(t):
    t.run(t.dataset(), "--save-map", t.path("out", "trajectory.txt"))


@case("save-map-existing-file", "--save-map an existing text file of the user's (not a map)", 1,
      r"--save-map .*notes\.txt exists and is not a file this command writes")
def _(t):
    notes = keep(t, "notes.txt")
    t.run(t.dataset(), "--save-map", notes)
    unchanged(t, notes, "notes.txt")


@case("save-map-fifo", "--save-map a FIFO", 1, r"--save-map .*FIFO.*only a regular file is ever replaced")
def _(t):
    os.mkfifo(t.path("m.map"))
    t.run(t.dataset(), "--save-map", t.path("m.map"))


@case("save-map-device", "--save-map /dev/null (as root the rename would replace the device)", 1,
      r"--save-map /dev/null: /dev is a system folder")
def _(t):
    t.run(t.dataset(), "--save-map", "/dev/null")
    if not os.path.exists("/dev/null") or not stat.S_ISCHR(os.stat("/dev/null").st_mode):
        t.problem("outside", "/dev/null is no longer the device")


@case("save-map-in-place", "--load-map m.map --save-map m.map: the map extended in place (the contract)", 0)
def _(t):
    _, reference = t.suite.reference()
    saved = t.path("m.map")
    with open(reference, "rb") as a, open(saved, "wb") as b:
        b.write(a.read())
    before = os.path.getsize(saved)
    t.writable.add(saved)
    t.run(t.dataset(), "--max-frames", 30, "--load-map", saved, "--save-map", saved, frames=(30, 30))
    check_map(t, saved)
    if os.path.getsize(saved) == before:
        t.problem("other", "the map file was not rewritten")


# --- --out -----------------------------------------------------------------

@case("out-root", "--out / (#47: 11 files written into the root folder)", 1, r"--out /: / is a system folder",
      short=True)
def _(t):
    before = {n for n in RUN_NAMES if os.path.lexists(os.path.join("/", n))}
    t.sgslam("run", "--dataset", t.dataset(), "--out", "/")
    absent_after(t, "/", [n for n in RUN_NAMES if n not in before])


@case("out-system-folder", "--out /etc/sgslam-faults (a new folder in a system folder)", 1,
      r"--out /etc/sgslam-faults: .*system folder")
def _(t):
    t.sgslam("run", "--dataset", t.dataset(), "--out", "/etc/sgslam-faults")
    if os.path.lexists("/etc/sgslam-faults"):
        subprocess.run(["rm", "-rf", "/etc/sgslam-faults"])
        t.problem("outside", "/etc/sgslam-faults was made")


@case("out-dataset-images", "--out the dataset's rgb/ folder", 1, r"--out .*rgb is a folder of the dataset's images")
def _(t):
    ds = t.dataset()
    t.sgslam("run", "--dataset", ds, "--out", os.path.join(ds, "rgb"))


@case("out-dataset-other-spelling", "--out the dataset folder spelled DATASET/rgb/..", 1,
      r"is the dataset folder")
def _(t):
    ds = t.dataset()
    t.sgslam("run", "--dataset", ds, "--out", os.path.join(ds, "rgb", ".."))


@case("out-holds-config", "--config out/config_used.yaml --out out (the run would rewrite its own config)", 1,
      r"config_used\.yaml is the configuration file given with --config")
def _(t):
    ds = t.dataset()
    config = keep(t, "out", "config_used.yaml")
    with open(config, "w", encoding="utf-8") as f:
        f.write("orb: {features: 900}\n")
    t.writable.add(t.path("out"))
    t.sgslam("run", "--dataset", ds, "--out", t.path("out"), "--config", config)
    with open(config, encoding="utf-8") as f:
        if f.read() != "orb: {features: 900}\n":
            t.problem("outside", "the configuration file changed")


# --- temporary files a killed run left ----------------------------------------

@case("stale-temp-removed", "temporary files of a killed run (a dead PID) beside trajectory.txt and the --save-map "
      "file; one of a live writer and a user's file of a like name kept", 0,
      r"removed .*trajectory\.txt\.tmp-sgslam\.\S+\.0, left by a writer that was killed",
      short=True)
def _(t):
    dead = dead_pid()
    os.makedirs(t.path("out"))
    os.makedirs(t.path("maps"))
    stale = [temp_name(t.path("out", "trajectory.txt"), dead, "0"), temp_name(t.path("maps", "room.map"), dead, "3"),
             temp_name(t.path("maps", "room.map"), dead, "Xy12Ab")]
    live = temp_name(t.path("maps", "room.map"), os.getpid(), "1")  # this script is alive
    users = t.path("maps", f"room.map.tmp.{dead}.backup")  # a user's own file of a similar name
    for p in stale + [live, users]:
        with open(p, "w", encoding="utf-8") as f:
            f.write("partial")
    t.writable.add(t.path("maps"))
    t.run(t.dataset(), "--max-frames", 10, "--save-map", t.path("maps", "room.map"), frames=(10, 10))
    left = [os.path.basename(p) for p in stale if os.path.exists(p)]
    if left:
        t.problem("other", "not removed: " + ", ".join(left))
    if not os.path.exists(live):
        t.problem("outside", "the live writer's temporary file was removed")
    if not os.path.exists(users):
        t.problem("outside", "the user's room.map.tmp.<n>.backup was removed")
    check_map(t, t.path("maps", "room.map"))


# --- the other commands ----------------------------------------------------

@case("eval-plot-over-est", "eval --plot the --est trajectory", 1, r"--plot .* is the trajectory given with --est")
def _(t):
    gt, est = copy_eval_inputs(t)
    with open(est, "rb") as f:
        before = f.read()
    t.sgslam("eval", "--gt", gt, "--est", est, "--plot", est)
    with open(est, "rb") as f:
        if f.read() != before:
            t.problem("outside", "the estimate was overwritten")


@case("eval-errors-over-gt", "eval --errors the --gt trajectory", 1, r"--errors .* is the trajectory given with --gt")
def _(t):
    gt, est = copy_eval_inputs(t)
    t.sgslam("eval", "--gt", gt, "--est", est, "--errors", gt)


@case("eval-plot-existing-text", "eval --plot an existing file that is not a PNG", 1,
      r"--plot .*notes\.txt exists and is not a file this command writes")
def _(t):
    gt, est = copy_eval_inputs(t)
    notes = keep(t, "notes.txt")
    t.sgslam("eval", "--gt", gt, "--est", est, "--plot", notes)
    unchanged(t, notes, "notes.txt")


@case("eval-plot-and-errors-same", "eval --plot and --errors the same new file", 1, r"--errors .* is also --plot")
def _(t):
    gt, est = copy_eval_inputs(t)
    t.sgslam("eval", "--gt", gt, "--est", est, "--plot", t.path("x.png"), "--errors", t.path("x.png"))


@case("synth-out-system", "synth --out /usr/share/sgslam-faults", 1, r"--out /usr/share/sgslam-faults: .*system folder")
def _(t):
    t.sgslam("synth", "--preset", "static", "--frames", 3, "--out", "/usr/share/sgslam-faults")
    if os.path.lexists("/usr/share/sgslam-faults"):
        subprocess.run(["rm", "-rf", "/usr/share/sgslam-faults"])
        t.problem("outside", "/usr/share/sgslam-faults was made")


@case("demo-out-root", "demo --out /", 1, r"--out /: / is a system folder")
def _(t):
    t.sgslam("demo", "--out", "/")
    absent_after(t, "/", ["sequence", "run-sg"])


@case("vocab-train-over-list", "vocab train --images LIST --out LIST", 1,
      r"--out .*rgb\.txt is the image list given with --images")
def _(t):
    ds = t.dataset()
    t.sgslam("vocab", "train", "--images", os.path.join(ds, "rgb.txt"), "--out", os.path.join(ds, "rgb.txt"))


@case("vocab-train-existing-file", "vocab train --out an existing file that is not a vocabulary", 1,
      r"--out .*notes\.txt exists and is not a file this command writes")
def _(t):
    ds = t.dataset()
    notes = keep(t, "notes.txt")
    t.sgslam("vocab", "train", "--images", os.path.join(ds, "rgb.txt"), "--out", notes)
    unchanged(t, notes, "notes.txt")


def users_dataset(t, name):
    """A copy of the sequence that synth did not write (its sgslam.yaml a user's)."""
    ds = t.dataset(name)
    with open(os.path.join(ds, "sgslam.yaml"), "w", encoding="utf-8") as f:
        f.write("# my camera\ncamera: {fx: 525.0, fy: 525.0, cx: 319.5, cy: 239.5, depth_factor: 5000.0}\n")
    with open(os.path.join(ds, "rgb.txt"), encoding="utf-8") as f:
        return ds, f.read()


def lists_kept(t, ds, rgb):
    with open(os.path.join(ds, "rgb.txt"), encoding="utf-8") as f:
        if f.read() != rgb:
            t.problem("outside", "the user's rgb.txt was replaced")


@case("demo-over-user-sequence", "demo --out a folder whose sequence/ is a user's dataset (not written by synth)", 1,
      r"synth --force: .*sequence/rgb\.txt was not written by sgslam synth")
def _(t):
    ds, rgb = users_dataset(t, os.path.join("demo", "sequence"))
    t.sgslam("demo", "--out", t.path("demo"))
    lists_kept(t, ds, rgb)


@case("synth-force-over-dataset", "synth --force into a user's dataset (synth did not write it)", 1,
      r"synth --force: .*rgb\.txt was not written by sgslam synth")
def _(t):
    ds, rgb = users_dataset(t, "seq")
    t.sgslam("synth", "--preset", "static", "--frames", 3, "--force", "--out", ds)
    lists_kept(t, ds, rgb)


@case("demo-after-interrupted-demo", "demo stopped by SIGINT while generating its sequence, then demo again", 0)
def _(t):
    out = t.path("demo")
    t.writable.add(out)
    first = t.sgslam("demo", "--out", out, "--frames", 60, main=False,
                     driver=when_exists(os.path.join(out, "sequence", "rgb"), SIG.SIGINT, count=3))
    if first.status != 130:
        t.problem("status", f"the interrupted demo exited {first.describe()}, expected 130")
    t.sgslam("demo", "--out", out, "--frames", 30)


@case("save-map-is-out-folder", "--out mm.map --save-map mm.map (both new: the map would meet a folder at the end)", 1,
      r"--save-map .*mm\.map: --out .*mm\.map is a folder there")
def _(t):
    t.sgslam("run", "--dataset", t.dataset(), "--out", t.path("mm.map"), "--save-map", t.path("mm.map"))


@case("save-map-inside-output", "--save-map OUT/stats.json/m.map (a folder where the run's stats.json goes)", 1,
      r"--save-map .*would be inside the run's stats\.json")
def _(t):
    t.run(t.dataset(), "--save-map", t.path("out", "stats.json", "m.map"))


@case("synth-out-empty", "synth --out ''", 1, r"--out: an empty path")
def _(t):
    t.sgslam("synth", "--preset", "static", "--frames", 3, "--out", "")


@case("out-model-folder", "--out the detector's model folder (--model a copy of the shipped one)", 1,
      r"--out .* is the detector's model folder")
def _(t):
    shipped = os.path.join(os.path.dirname(t.suite.sgslam), "share", "sgslam", "models", "yolo-fastest-1.1-coco")
    if not os.path.isdir(shipped):
        raise SkipCase(f"no shipped model at {shipped}")
    model = t.path("model")
    shutil.copytree(shipped, model)
    t.sgslam("run", "--dataset", t.dataset(), "--mode", "sg", "--config", write_config(t, "detector: {backend: dnn}\n"),
             "--model", model, "--out", model)


@case("save-map-over-vocabulary", "--save-map the vocabulary loop.vocabulary names", 1,
      r"--save-map .*vocab is the vocabulary of loop\.vocabulary")
def _(t):
    if not t.suite.vocabulary():
        raise SkipCase("no shipped vocabulary beside the program")
    vocabulary = t.path("copy.vocab")
    shutil.copy(t.suite.vocabulary(), vocabulary)
    config = write_config(t, f"loop: {{vocabulary: {vocabulary}}}\n")
    t.run(t.dataset(), "--config", config, "--save-map", vocabulary)


@case("out-over-detections-file", "detector.detections_file out/detections.txt: the run would replace what it replays",
      1, r"the run's detections\.txt .* is the detections file of detector\.backend file")
def _(t):
    ds = t.dataset()
    os.makedirs(t.path("out"))
    shutil.copy(os.path.join(ds, "detections.txt"), t.path("out", "detections.txt"))
    config = write_config(t, f"detector: {{backend: file, detections_file: {t.path('out', 'detections.txt')}}}\n")
    t.writable.add(t.path("out"))
    t.sgslam("run", "--dataset", ds, "--mode", "sg", "--config", config, "--out", t.path("out"))


# --- --mcap ----------------------------------------------------------------

@case("mcap-existing-file", "--mcap an existing text file of the user's (not an MCAP file)", 1,
      r"--mcap .*notes\.txt exists and is not a file this command writes", short=True)
def _(t):
    notes = keep(t, "notes.txt")
    t.run(t.dataset(), "--mcap", notes)
    unchanged(t, notes, "notes.txt")


@case("mcap-is-output", "--mcap OUT/trajectory.txt", 1, r"--mcap .*trajectory\.txt is also the run's trajectory\.txt")
def _(t):
    t.run(t.dataset(), "--mcap", t.path("out", "trajectory.txt"))


@case("mcap-in-a-file", "--mcap in a folder that is a file of the user's", 1, r"--mcap .*notes\.txt")
def _(t):
    notes = keep(t, "notes.txt")
    t.run(t.dataset(), "--mcap", os.path.join(notes, "run.mcap"))
    unchanged(t, notes, "notes.txt")


@case("mcap-kept-on-failed-start", "--mcap over an earlier recording, --foxglove on a port in use: the run "
      "refused, the earlier recording kept", 1, r"--foxglove: cannot listen on 127\.0\.0\.1:\d+")
def _(t):
    import socket
    rec = t.path("rec.mcap")
    with open(rec, "wb") as f:
        f.write(b"\x89MCAP0\r\n an earlier recording")
    with open(rec, "rb") as f:
        before = f.read()
    busy = socket.socket()
    busy.bind(("127.0.0.1", 0))
    busy.listen(1)
    try:
        t.run(t.dataset(), "--mcap", rec, f"--foxglove={busy.getsockname()[1]}")
    finally:
        busy.close()
    with open(rec, "rb") as f:
        if f.read() != before:
            t.problem("lost", "the earlier recording was replaced by a run that never started")
    if os.path.exists(rec + ".part"):
        t.problem("outside", "rec.mcap.part left behind")
