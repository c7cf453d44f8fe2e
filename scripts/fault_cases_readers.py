"""Cases of scripts/faults.py (issue #47): readers: regular files only, headers before bodies, bounded reads, every error naming the file; duplicate YAML keys."""
import os
import re
import shutil
import struct

from fault_cases import SkipCase, append, case, replace_file

SPARSE_BYTES = 3 << 29  # 1.5 GiB of hole: read whole, it costs seconds and as much memory
MAP_HEADER = 52  # magic (8), version (4), payload size (8), SHA-256 (32)
VOCAB_HEADER = 32  # magic (8), version, k, L, node count (4 each), training images (8)


# --- helpers --------------------------------------------------------------

def fifo(path):
    """A FIFO (named pipe) at path, in place of what was there: a reader that opens
    it waits for a writer, for ever."""
    if os.path.lexists(path):
        os.remove(path)
    os.mkfifo(path)
    return path


def sparse(path, size, head=b""):
    """A file of size bytes, head then a hole (zeros that take no disk space)."""
    replace_file(path, head)
    os.truncate(path, size)
    return path


def quick_and_small(t, seconds=10):
    """The refusal came at once and cost little memory (the suite's --rss-limit)."""
    proc = t.proc
    if proc.seconds > seconds * t.suite.timeout_scale:
        t.problem("other", f"took {proc.seconds:.1f} s to refuse")
    if proc.max_rss_mib > t.suite.rss_limit_mib:
        t.problem("other", f"peak RSS {proc.max_rss_mib:.0f} MiB (limit {t.suite.rss_limit_mib:.0f})")
    t.notes.append(f"peak RSS {proc.max_rss_mib:.0f} MiB, {proc.seconds:.1f} s")


def reference_map(t):
    _, saved = t.suite.reference()
    with open(saved, "rb") as f:
        return f.read()


def shipped_vocabulary(t):
    path = t.suite.vocabulary()
    if path is None:
        raise SkipCase("skipped: no vocabulary beside the program")
    with open(path, "rb") as f:
        return f.read()


def use_vocabulary(t, ds, path):
    append(os.path.join(ds, "sgslam.yaml"), f"loop:\n  vocabulary: {path}\n")


def run_folder(t):
    """A copy of the reference run's output folder, for sgslam view."""
    out, _ = t.suite.reference()
    folder = t.path("run")
    shutil.copytree(out, folder)
    return folder


def view(t, folder):
    """sgslam view on folder: a bad file must stop it before it serves (it would
    serve until a signal: the case's time bound reports that as a hang)."""
    t.sgslam("view", folder, "--port", "0", timeout=30)


def lines_of(path):
    with open(path, encoding="utf-8") as f:
        return f.read().splitlines()


# --- FIFOs, folders and devices in place of files --------------------------

def dataset_fifo_case(case_name, name, short=False):
    @case(case_name, f"{name} a FIFO (named pipe) in the dataset folder (#47: ignored, or a hang)", 1,
          rf"{re.escape(name)}: is a FIFO", short=short, timeout=30)
    def _(t):
        ds = t.dataset()
        fifo(os.path.join(ds, name))
        t.run(ds)
        quick_and_small(t)


dataset_fifo_case("fifo-associations", "associations.txt", short=True)
dataset_fifo_case("fifo-groundtruth", "groundtruth.txt")
dataset_fifo_case("fifo-dataset-yaml", "sgslam.yaml")
dataset_fifo_case("fifo-detections", "detections.txt")
dataset_fifo_case("fifo-mask-list", "mask.txt")


@case("folder-groundtruth", "groundtruth.txt a folder in the dataset folder (#47: taken for no ground truth)", 1,
      r"groundtruth\.txt: is a folder", timeout=30)
def _(t):
    ds = t.dataset()
    os.remove(os.path.join(ds, "groundtruth.txt"))
    os.makedirs(os.path.join(ds, "groundtruth.txt"))
    t.run(ds)


@case("fifo-rgb-image", "frame 4's RGB image a FIFO (named pipe)", 1, r"rgb/\S+\.png: is a FIFO", timeout=60)
def _(t):
    ds = t.dataset()
    fifo(os.path.join(ds, t.suite.rgb[4]))
    t.run(ds, "--max-frames", 8, frames=(4, 4))


@case("fifo-config", "--config a FIFO (named pipe) (#47: YAML::LoadFile waited on it)", 1,
      r"conf\.yaml is a FIFO", timeout=30)
def _(t):
    t.run(t.dataset(), "--config", fifo(t.path("conf.yaml")))
    quick_and_small(t)


@case("fifo-load-map", "--load-map a FIFO (named pipe)", 1, r"map file \S*m\.map: is a FIFO", timeout=30)
def _(t):
    t.run(t.dataset(), "--load-map", fifo(t.path("m.map")))
    quick_and_small(t)


@case("fifo-vocabulary", "loop.vocabulary a FIFO (named pipe)", 1, r"v\.vocab is a FIFO", timeout=30)
def _(t):
    ds = t.dataset()
    use_vocabulary(t, ds, fifo(t.path("v.vocab")))
    t.run(ds)
    quick_and_small(t)


@case("fifo-vocab-info", "vocab info on a FIFO (named pipe) (#47: a hang)", 1, r"vocabulary \S*v\.vocab: is a FIFO",
      timeout=30)
def _(t):
    t.sgslam("vocab", "info", fifo(t.path("v.vocab")))
    quick_and_small(t)


@case("fifo-vocab-eval", "vocab eval on a FIFO (named pipe) (#47: a hang)", 1, r"vocabulary \S*v\.vocab: is a FIFO",
      timeout=30)
def _(t):
    t.sgslam("vocab", "eval", fifo(t.path("v.vocab")), "--dataset", t.dataset())
    quick_and_small(t)


@case("fifo-map-info", "map info on a FIFO (named pipe)", 1, r"map file \S*m\.map: is a FIFO", timeout=30)
def _(t):
    t.sgslam("map", "info", fifo(t.path("m.map")))
    quick_and_small(t)


@case("folder-vocab-info", "vocab info on a folder (#47: 'unexpected failure', no file named)", 1,
      r"vocabulary \S*v\.vocab: is a folder", timeout=30)
def _(t):
    os.makedirs(t.path("v.vocab"))
    t.sgslam("vocab", "info", t.path("v.vocab"))


@case("devzero-load-map", "--load-map /dev/zero", 1, r"map file /dev/zero: is a device", timeout=30)
def _(t):
    t.run(t.dataset(), "--load-map", "/dev/zero")
    quick_and_small(t)


@case("devzero-vocabulary", "loop.vocabulary: /dev/zero", 1, r"/dev/zero is a device", timeout=30)
def _(t):
    ds = t.dataset()
    use_vocabulary(t, ds, "/dev/zero")
    t.run(ds)
    quick_and_small(t)


@case("devzero-vocab-info", "vocab info /dev/zero (#47: read until bad_alloc)", 1, r"/dev/zero: is a device",
      timeout=30)
def _(t):
    t.sgslam("vocab", "info", "/dev/zero")
    quick_and_small(t)


@case("devzero-config", "--config /dev/zero", 1, r"config file /dev/zero is a device", timeout=30)
def _(t):
    t.run(t.dataset(), "--config", "/dev/zero")
    quick_and_small(t)


# --- headers that lie, and huge files -------------------------------------

@case("map-header-huge", "--load-map the reference map with a header claiming a 1 TB payload", 1,
      r"lies\.map: truncated or padded: the header says 1099511627776 payload bytes", timeout=30)
def _(t):
    data = bytearray(reference_map(t))
    data[12:20] = struct.pack("<Q", 1 << 40)
    replace_file(t.path("lies.map"), bytes(data))
    t.run(t.dataset(), "--load-map", t.path("lies.map"))
    quick_and_small(t)


@case("vocab-header-huge", "vocab info on the shipped vocabulary with a header claiming 50 million nodes", 1,
      r"lies\.vocab: \d+ bytes, expected 1900000096 for the 50000000 nodes", timeout=30)
def _(t):
    data = bytearray(shipped_vocabulary(t))
    data[20:24] = struct.pack("<I", 50_000_000)
    replace_file(t.path("lies.vocab"), bytes(data))
    t.sgslam("vocab", "info", t.path("lies.vocab"))
    quick_and_small(t)


@case("sparse-load-map", "--load-map a 1.5 GiB sparse file of zeros (#47: read whole, 2 GB, bad_alloc)", 1,
      r"zeros\.map: not an sgslam map file", short=True, timeout=30)
def _(t):
    t.run(t.dataset(), "--load-map", sparse(t.path("zeros.map"), SPARSE_BYTES))
    quick_and_small(t)


@case("sparse-map-info", "map info on a 1.5 GiB sparse file of zeros (#47)", 1, r"zeros\.map: not an sgslam map file",
      timeout=30)
def _(t):
    t.sgslam("map", "info", sparse(t.path("zeros.map"), SPARSE_BYTES))
    quick_and_small(t)


@case("sparse-vocab-info", "vocab info on a 1.5 GiB sparse file of zeros", 1, r"zeros\.vocab: not an sgslam vocabulary",
      timeout=30)
def _(t):
    t.sgslam("vocab", "info", sparse(t.path("zeros.vocab"), SPARSE_BYTES))
    quick_and_small(t)


@case("sparse-map-header-fits", "map info on a map header whose payload size fits 1.5 GiB of zeros behind it "
      "(hashed in pieces, never held)", 1, r"zeros\.map: checksum mismatch", timeout=60)
def _(t):
    head = bytearray(reference_map(t)[:MAP_HEADER])
    head[12:20] = struct.pack("<Q", SPARSE_BYTES - MAP_HEADER)
    t.sgslam("map", "info", sparse(t.path("zeros.map"), SPARSE_BYTES, bytes(head)))
    quick_and_small(t, seconds=30)


@case("sparse-vocab-header-fits", "vocab info on a vocabulary header whose 40 million nodes fit 1.5 GB of zeros behind "
      "it (hashed in pieces, never held)", 1, r"zeros\.vocab: checksum mismatch", timeout=60)
def _(t):
    head = bytearray(shipped_vocabulary(t)[:VOCAB_HEADER])
    nodes = 40_000_000
    head[20:24] = struct.pack("<I", nodes)
    t.sgslam("vocab", "info", sparse(t.path("zeros.vocab"), VOCAB_HEADER + 38 * nodes + 64, bytes(head)))
    quick_and_small(t, seconds=30)


@case("groundtruth-sparse", "eval --gt a 1.5 GiB sparse file (zeros, no newline)", 1,
      r"groundtruth\.txt: \d+ bytes, more than", timeout=30)
def _(t):
    ds = t.dataset()
    sparse(os.path.join(ds, "groundtruth.txt"), SPARSE_BYTES)
    t.sgslam("eval", "--gt", os.path.join(ds, "groundtruth.txt"), "--est", os.path.join(ds, "groundtruth.txt"))
    quick_and_small(t)


@case("rgb-list-long-line", "rgb.txt with a line of 1 MB (no list's: a binary file without newlines)", 1,
      r"rgb\.txt:4: a line longer than 65536 bytes", timeout=30)
def _(t):
    ds = t.dataset()
    lines = lines_of(os.path.join(ds, "rgb.txt"))
    lines[3] = lines[3] + " " + "x" * (1 << 20)
    replace_file(os.path.join(ds, "rgb.txt"), ("\n".join(lines) + "\n").encode())
    t.run(ds)
    quick_and_small(t)


# --- sgslam view on damaged run outputs -----------------------------------

PLY_HEADER = ("ply\nformat binary_little_endian 1.0\nelement vertex {}\nproperty float x\nproperty float y\n"
              "property float z\nproperty uchar red\nproperty uchar green\nproperty uchar blue\nend_header\n")


@case("view-cloud-huge", "view: cloud.ply of 220 bytes claiming 150 million points (#47: 1.8 GB, then 'truncated')",
      1, r"cloud\.ply: its header claims 150000000 points", short=True, timeout=30)
def _(t):
    folder = run_folder(t)
    header = PLY_HEADER.format(150_000_000).encode()
    replace_file(os.path.join(folder, "cloud.ply"), header + bytes(220 - len(header)))
    view(t, folder)
    quick_and_small(t)


@case("view-cloud-count-overflow", "view: cloud.ply claiming 99999999999999999999 points (#47: 'unexpected failure')",
      1, r"cloud\.ply: bad vertex count", timeout=30)
def _(t):
    folder = run_folder(t)
    replace_file(os.path.join(folder, "cloud.ply"), PLY_HEADER.format("9" * 20).encode() + bytes(30))
    view(t, folder)


def view_json_case(name, file, text, message):
    @case(name, f"view: {file} is {text} (#47: the JSON library's type_error, no file named)", 1, message, timeout=30)
    def _(t):
        folder = run_folder(t)
        replace_file(os.path.join(folder, file), text.encode())
        view(t, folder)


view_json_case("view-stats-array", "stats.json", "[1, 2, 3]", r"stats\.json: a JSON array, not the object")
view_json_case("view-stats-number", "stats.json", "42", r"stats\.json: a JSON number, not the object")
view_json_case("view-stats-field-types", "stats.json", '{"dataset": 5, "mode": ["sg"], "frames": "many"}',
               r"stats\.json: 'dataset' must be a string")
view_json_case("view-stats-frames-string", "stats.json", '{"mode": "sg", "frames": "many"}',
               r"stats\.json: 'frames' must be a count")
view_json_case("view-objects-string", "objects.json", '"objects"', r"objects\.json: a JSON string, not the object")
view_json_case("view-objects-not-list", "objects.json", '{"objects": {"class": "cup"}}',
               r"objects\.json: 'objects' must be a list")
view_json_case("view-objects-field", "objects.json", '{"objects": [{"class": 1, "confidence": "high"}]}',
               r"objects\.json: object 1 lacks")


@case("view-octomap-deep", "view: octomap.bt whose node tree has children below children for 4 MiB "
      "(OctoMap 1.9.7's reader recurses until the stack overflows: SIGSEGV)", 1, r"octomap\.bt: its node tree is deeper",
      timeout=30)
def _(t):
    folder = run_folder(t)
    path = os.path.join(folder, "octomap.bt")
    with open(path, "rb") as f:
        data = f.read()
    head = data[:data.index(b"\ndata\n") + len(b"\ndata\n")]
    replace_file(path, head + b"\xff" * (4 << 20))
    view(t, folder)


@case("view-octomap-cut", "view: octomap.bt cut to two thirds", 1, r"octomap\.bt: its node tree is cut short",
      timeout=30)
def _(t):
    folder = run_folder(t)
    path = os.path.join(folder, "octomap.bt")
    with open(path, "rb") as f:
        data = f.read()
    replace_file(path, data[:len(data) * 2 // 3])
    view(t, folder)


@case("view-octomap-fifo", "view: octomap.bt a FIFO (named pipe)", 1, r"octomap\.bt: is a FIFO", timeout=30)
def _(t):
    folder = run_folder(t)
    fifo(os.path.join(folder, "octomap.bt"))
    view(t, folder)


# --- duplicate YAML keys --------------------------------------------------

@case("dup-config-key", "--config with orb.features given twice (#47: yaml-cpp kept the first, silently)", 1,
      r"dup\.yaml:3: 'orb\.features' given twice, at lines 2 and 3")
def _(t):
    replace_file(t.path("dup.yaml"), b"orb:\n  features: 900\n  features: 1200\n")
    t.run(t.dataset(), "--config", t.path("dup.yaml"))


@case("dup-config-section", "--config with the orb section given twice (#47: the second dropped, silently)", 1,
      r"dup\.yaml:5: 'orb' given twice, at lines 1 and 5")
def _(t):
    replace_file(t.path("dup.yaml"), b"orb:\n  features: 900\ndynamic:\n  mode: sg\norb:\n  levels: 4\n")
    t.run(t.dataset(), "--config", t.path("dup.yaml"))


@case("dup-config-table-entry", "--config with a class given twice in detector.dynamic_weight", 1,
      r"dup\.yaml:4: 'detector\.dynamic_weight\.person' given twice, at lines 3 and 4")
def _(t):
    replace_file(t.path("dup.yaml"), b"detector:\n  dynamic_weight:\n    person: 1.0\n    person: 0.2\n")
    t.run(t.dataset(), "--config", t.path("dup.yaml"))


def duplicate_in_dataset(t, ds, nested):
    """The sequence's sgslam.yaml with camera.fx given again (nested) or a second
    camera section appended; returns the two lines."""
    path = os.path.join(ds, "sgslam.yaml")
    lines = lines_of(path)
    first = next(i for i, l in enumerate(lines) if l.startswith("  fx:" if nested else "camera:")) + 1
    if nested:
        lines.insert(first + 1, "  fx: 500.0")
        second = first + 2
    else:
        lines += ["camera:", "  fx: 500.0"]
        second = len(lines) - 1
    replace_file(path, ("\n".join(lines) + "\n").encode())
    return first, second


def dataset_duplicate_case(name, nested, short, with_config):
    what = "camera.fx given twice" if nested else "a second camera section"
    key = r"camera\.fx" if nested else "camera"

    @case(name, f"the sequence's sgslam.yaml with {what}" + (" and --config orb.yaml" if with_config else ""), 1,
          rf"sgslam\.yaml:\d+: '{key}' given twice", short=short)
    def _(t):
        ds = t.dataset()
        first, second = duplicate_in_dataset(t, ds, nested)
        t.messages.append(rf"sgslam\.yaml:{second}: '{key}' given twice, at lines {first} and {second}")
        args = []
        if with_config:
            replace_file(t.path("orb.yaml"), b"orb:\n  features: 900\n")
            args = ["--config", t.path("orb.yaml")]
        t.run(ds, *args)


dataset_duplicate_case("dup-dataset-section", nested=False, short=True, with_config=False)
dataset_duplicate_case("dup-dataset-key", nested=True, short=False, with_config=False)
dataset_duplicate_case("dup-dataset-section-with-config", nested=False, short=False, with_config=True)
