"""Cases of scripts/faults.py (issue #47): the paths the program writes: never the dataset, a file in use, another output or a system folder; temporary files a killed run left."""
import os
import re

import fault_files as files
from fault_cases import BASE_FRAMES, SIG, SkipCase, case, edit, append, replace_file, garbage, stats_of
import stat
import subprocess
import sys

from fault_cases import check_map, copy_eval_inputs

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
      "file; one of a live writer", 0, r"removed .*trajectory\.txt\.tmp\.\d+\.0, left by a writer that was killed",
      short=True)
def _(t):
    dead = dead_pid()
    os.makedirs(t.path("out"))
    os.makedirs(t.path("maps"))
    stale = [t.path("out", f"trajectory.txt.tmp.{dead}.0"), t.path("maps", f"room.map.tmp.{dead}.3"),
             t.path("maps", f"room.map.tmp.{dead}.Xy12Ab")]
    live = t.path("maps", f"room.map.tmp.{os.getpid()}.1")  # this script is alive, and was before the file
    for p in stale + [live]:
        with open(p, "w", encoding="utf-8") as f:
            f.write("partial")
    t.writable.add(t.path("maps"))
    t.run(t.dataset(), "--max-frames", 10, "--save-map", t.path("maps", "room.map"), frames=(10, 10))
    left = [os.path.basename(p) for p in stale if os.path.exists(p)]
    if left:
        t.problem("other", "not removed: " + ", ".join(left))
    if not os.path.exists(live):
        t.problem("outside", "the live writer's temporary file was removed")
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


@case("demo-over-user-sequence", "demo --out a folder whose sequence/ is a user's dataset (not written by synth)", 1,
      r"holds a sequence that `sgslam synth` did not write")
def _(t):
    ds = t.dataset(os.path.join("demo", "sequence"))
    rgb = os.path.join(ds, "rgb.txt")
    with open(rgb, encoding="utf-8") as f:
        text = f.read().replace("sgslam synth", "a camera")
    with open(rgb, "w", encoding="utf-8") as f:
        f.write(text)
    t.sgslam("demo", "--out", t.path("demo"))
    with open(rgb, encoding="utf-8") as f:
        if f.read() != text:
            t.problem("outside", "the user's rgb.txt was replaced")
