"""Cases of scripts/faults.py (registered in fault_cases.CASES): damaged lists and
images, and bad configurations and command lines."""
import os
import random
import re

import fault_files as files
from fault_cases import (BASE_FRAMES, SkipCase, append, case, edit, frame_file, garbage, list_lines, replace_file,
                         write_lines)


# --- lists and images -----------------------------------------------------

@case("rgb-list-missing", "rgb.txt deleted", 1, r"missing .*rgb\.txt", short=True)
def _(t):
    ds = t.dataset()
    os.remove(os.path.join(ds, "rgb.txt"))
    t.run(ds)


@case("rgb-list-empty", "rgb.txt empty", 1, r"empty sequence.*rgb\.txt has 0")
def _(t):
    ds = t.dataset()
    replace_file(os.path.join(ds, "rgb.txt"), b"")
    t.run(ds)


@case("rgb-list-binary", "rgb.txt 4 KiB of random bytes", 1, r"rgb\.txt:\d+", short=True)
def _(t):
    ds = t.dataset()
    replace_file(os.path.join(ds, "rgb.txt"), garbage(4096))
    t.run(ds)


@case("rgb-list-shuffled", "rgb.txt's lines in random order (sorted on reading)", 0)
def _(t):
    ds = t.dataset()
    lines = list_lines(os.path.join(ds, "rgb.txt"))
    body = lines[3:]
    random.Random(1).shuffle(body)
    write_lines(os.path.join(ds, "rgb.txt"), lines[:3] + body)
    t.run(ds, frames=(BASE_FRAMES, BASE_FRAMES))


@case("rgb-list-nul", "a NUL byte inside a path in rgb.txt (it would end the path there)", 1,
      r"rgb\.txt:\d+: a NUL byte")
def _(t):
    ds = t.dataset()
    lines = list_lines(os.path.join(ds, "rgb.txt"))
    stamp, path = lines[12].split()
    lines[12] = f"{stamp} {path}\0.png"
    write_lines(os.path.join(ds, "rgb.txt"), lines)
    t.run(ds, "--max-frames", 16)


@case("rgb-list-duplicate", "frame 10 listed twice in rgb.txt and depth.txt (two frames, one timestamp)", 1,
      r"rgb\.txt:\d+: timestamp .* repeats")
def _(t):
    ds = t.dataset()
    for name in ("rgb.txt", "depth.txt"):
        lines = list_lines(os.path.join(ds, name))
        write_lines(os.path.join(ds, name), lines[:13] + [lines[13]] + lines[13:])
    t.run(ds, "--max-frames", 16)


@case("rgb-list-nan", "timestamp 'nan' in rgb.txt", 1, r"rgb\.txt:\d+.*timestamp")
def _(t):
    ds = t.dataset()
    edit(os.path.join(ds, "rgb.txt"), r"^\d+\.\d+ ", "nan ")
    t.run(ds)


@case("rgb-list-inf", "timestamp 'inf' in rgb.txt", 1, r"rgb\.txt:\d+.*timestamp")
def _(t):
    ds = t.dataset()
    edit(os.path.join(ds, "rgb.txt"), r"^\d+\.\d+ ", "inf ")
    t.run(ds)


@case("rgb-list-crlf", "rgb.txt and depth.txt with Windows line ends", 0)
def _(t):
    ds = t.dataset()
    for name in ("rgb.txt", "depth.txt"):
        write_lines(os.path.join(ds, name), list_lines(os.path.join(ds, name)), newline="\r\n")
    t.run(ds, "--max-frames", 8, frames=(8, 8))


@case("rgb-list-outside", "frame 3's RGB listed as ../../../../../../etc/passwd", 1, r"passwd")
def _(t):
    ds = t.dataset()
    edit(os.path.join(ds, "rgb.txt"), re.escape(t.suite.rgb[3]), "../../../../../../etc/passwd")
    t.run(ds, "--max-frames", 8, frames=(3, 3))


@case("rgb-list-device", "frame 3's RGB listed as /dev/zero", 1, r"/dev/zero")
def _(t):
    ds = t.dataset()
    edit(os.path.join(ds, "rgb.txt"), re.escape(t.suite.rgb[3]), "/dev/zero")
    t.run(ds, "--max-frames", 8, frames=(3, 3))


@case("associations-binary", "associations.txt of random bytes", 1, r"associations\.txt:\d+")
def _(t):
    ds = t.dataset()
    replace_file(os.path.join(ds, "associations.txt"), garbage(4096, seed=5))
    t.run(ds)


@case("groundtruth-nan", "groundtruth.txt with 'nan' for x in its first pose", 0, r"no ATE.*groundtruth\.txt")
def _(t):
    ds = t.dataset()
    edit(os.path.join(ds, "groundtruth.txt"), r"^(\d\S*) \S+", r"\1 nan")
    t.run(ds, "--max-frames", 8, frames=(8, 8))


@case("groundtruth-binary", "groundtruth.txt of random bytes", 0, r"no ATE.*groundtruth\.txt")
def _(t):
    ds = t.dataset()
    replace_file(os.path.join(ds, "groundtruth.txt"), garbage(8192, seed=3))
    t.run(ds, "--max-frames", 8, frames=(8, 8))


@case("depth-missing", "frame 20's depth image deleted", 1, r"image missing.*depth/")
def _(t):
    ds = t.dataset()
    os.remove(frame_file(t, ds, "depth", 20))
    t.run(ds, "--max-frames", 24, frames=(20, 20))


@case("depth-8bit", "frame 10's depth an 8-bit PNG", 1, r"depth/\S+\.png.*16-bit")
def _(t):
    ds = t.dataset()
    replace_file(frame_file(t, ds, "depth", 10), files.png_bytes(640, 480, 8, 0, 100))
    t.run(ds, "--max-frames", 12, frames=(10, 10))


@case("rgb-16bit", "frame 10's RGB a 16-bit PNG", 1, r"rgb/\S+\.png.*8-bit")
def _(t):
    ds = t.dataset()
    replace_file(frame_file(t, ds, "rgb", 10), files.png_bytes(640, 480, 16, 2, 30000))
    t.run(ds, "--max-frames", 12, frames=(10, 10))


@case("depth-size-differs", "frame 5's depth 320x240 beside a 640x480 RGB", 1, r"320x240")
def _(t):
    ds = t.dataset()
    replace_file(frame_file(t, ds, "depth", 5), files.png_bytes(320, 240, 16, 0, 10000))
    t.run(ds, "--max-frames", 8, frames=(5, 5))


@case("camera-size-differs", "camera 320x240 in sgslam.yaml, images 640x480", 1, r"camera\.width")
def _(t):
    ds = t.dataset()
    path = os.path.join(ds, "sgslam.yaml")
    for key, value in (("width", "320"), ("height", "240"), ("cx", "159.5"), ("cy", "119.5")):
        edit(path, rf"^  {key}: .*$", f"  {key}: {value}")
    t.run(ds, frames=(0, 0))


@case("image-empty", "frame 7's RGB an empty file", 1, r"rgb/\S+\.png")
def _(t):
    ds = t.dataset()
    replace_file(frame_file(t, ds, "rgb", 7), b"")
    t.run(ds, "--max-frames", 10, frames=(7, 7))


@case("png-truncated", "frame 12's RGB PNG cut to half its length", 1, r"rgb/")
def _(t):
    ds = t.dataset()
    path = frame_file(t, ds, "rgb", 12)
    with open(path, "rb") as f:
        data = f.read()
    replace_file(path, data[:len(data) // 2])
    t.run(ds, "--max-frames", 14, frames=(12, 12))


@case("mask-unreadable", "frame 0's ground-truth mask (scoring only) not an image", 1, r"mask/", short=True)
def _(t):
    ds = t.dataset()
    replace_file(os.path.join(ds, list_lines(os.path.join(ds, "mask.txt"))[3].split()[1]), b"not a png\n")
    t.run(ds, "--max-frames", 8, frames=(1, 1))


@case("all-depth-zero", "every depth pixel 0 in 10 frames", 0, r"no frame was tracked")
def _(t):
    ds = t.dataset()
    zero = files.png_bytes(640, 480, 16, 0, 0)
    for i in range(10):
        replace_file(frame_file(t, ds, "depth", i), zero)
    t.run(ds, "--max-frames", 10, frames=(10, 10))


@case("one-frame", "a sequence of one frame", 0)
def _(t):
    ds = t.dataset()
    for name in ("rgb.txt", "depth.txt"):
        write_lines(os.path.join(ds, name), list_lines(os.path.join(ds, name))[:4])
    t.run(ds, frames=(1, 1))


# --- configuration and command line ---------------------------------------

@case("config-unknown-key", "orb.featurez: 1000 (a typo)", 1, r"sgslam\.yaml:\d+.*featurez.*did you mean")
def _(t):
    ds = t.dataset()
    append(os.path.join(ds, "sgslam.yaml"), "orb:\n  featurez: 1000\n")
    t.run(ds)


@case("config-yaml-syntax", "a YAML syntax error (an unclosed '[')", 1, r"sgslam\.yaml")
def _(t):
    ds = t.dataset()
    append(os.path.join(ds, "sgslam.yaml"), "orb: [features: 1000\n")
    t.run(ds)


@case("config-wrong-type", "orb.features: many", 1, r"orb\.features must be an integer")
def _(t):
    ds = t.dataset()
    append(os.path.join(ds, "sgslam.yaml"), "orb:\n  features: many\n")
    t.run(ds)


@case("config-binary", "--config a file of random bytes", 1, r"junk\.yaml")
def _(t):
    ds = t.dataset()
    replace_file(t.path("junk.yaml"), garbage(2048, seed=9))
    t.run(ds, "--config", t.path("junk.yaml"))


@case("config-not-found", "--config nosuch (neither a file nor a shipped name)", 1, r"config file not found: nosuch")
def _(t):
    t.run(t.dataset(), "--config", "nosuch")


@case("config-folder", "--config a folder", 1, r"conf\.yaml.*(folder|not a file)", short=True)
def _(t):
    os.makedirs(t.path("conf.yaml"))
    t.run(t.dataset(), "--config", t.path("conf.yaml"))


@case("max-frames-negative", "--max-frames -5", 2, r"--max-frames")
def _(t):
    t.run(t.dataset(), "--max-frames", "-5")


@case("max-frames-huge", "--max-frames 99999999999999999999999 (beyond 64 bits)", 2, r"--max-frames", short=True)
def _(t):
    t.run(t.dataset(), "--max-frames", "99999999999999999999999")


@case("max-frames-uint64", "--max-frames 18446744073709551615 (the largest 64-bit value: all frames)", 0)
def _(t):
    t.run(t.dataset(), "--max-frames", "18446744073709551615", frames=(BASE_FRAMES, BASE_FRAMES))


@case("mode-unknown", "--mode fast", 2, r"--mode")
def _(t):
    t.run(t.dataset(), "--mode", "fast")


@case("dataset-missing", "--dataset a folder that does not exist", 1, r"dataset folder not found")
def _(t):
    t.run(t.path("nosuch"))


@case("dataset-is-file", "--dataset a file", 1, r"dataset folder not found")
def _(t):
    replace_file(t.path("file"), b"x\n")
    t.run(t.path("file"))


@case("dataset-unreadable", "--dataset chmod 000", 1, r"seq")
def _(t):
    if os.geteuid() == 0:
        raise SkipCase("skipped: running as root, which reads a chmod 000 folder")
    ds = t.dataset()
    os.chmod(ds, 0)
    try:
        t.run(ds)
    finally:
        os.chmod(ds, 0o755)


@case("out-unwritable", "--out a chmod 555 folder", 1, r"not written")
def _(t):
    if os.geteuid() == 0:
        raise SkipCase("skipped: running as root, which writes into a chmod 555 folder")
    ds = t.dataset()
    os.makedirs(t.path("out"))
    os.chmod(t.path("out"), 0o555)
    try:
        t.run(ds, "--max-frames", 5)
    finally:
        os.chmod(t.path("out"), 0o755)


@case("out-is-file", "--out an existing file", 1, r"output folder")
def _(t):
    replace_file(t.path("out"), b"keep me\n")
    t.run(t.dataset())
    with open(t.path("out"), "rb") as f:
        if f.read() != b"keep me\n":
            t.problem("outside", "the file named by --out was changed")


@case("out-under-file", "--out a folder below a file", 1, r"output folder")
def _(t):
    replace_file(t.path("file"), b"keep me\n")
    t.writable.add(t.path("file", "out"))
    t.sgslam("run", "--dataset", t.dataset(), "--out", t.path("file", "out"))


@case("out-name-too-long", "--out with a 300-character folder name", 1, r"output folder")
def _(t):
    t.run(t.dataset(), out="x" * 300)


@case("out-path-too-long", "--out a path of 5000 characters (beyond PATH_MAX)", 1, r"output folder")
def _(t):
    t.run(t.dataset(), out=os.path.join(*["d" * 200] * 25))


@case("out-symlink-loop", "--out a symlink to itself", 1, r"output folder")
def _(t):
    os.symlink("loop", t.path("loop"))
    t.run(t.dataset(), out="loop")
