#!/usr/bin/env python3
"""The core library's layering (docs/development.md, "Layers"): each folder of
src/sgslam may include only itself and the folders below it in LAYERS, so there is
no folder cycle, and no file of the core includes ROS, HTTP or GUI headers.
Prints the folder graph; exits 1 naming every include that breaks a rule.
  scripts/check_layers.py [SOURCE_DIR]"""
import os
import re
import sys

# Lowest first. A folder may include the folders before it.
LAYERS = ["common", "camera", "io", "features", "vocab", "geometry", "optim", "detection", "synth", "map",
          "matching", "loop", "dynamic", "movers", "tracking", "mapping", "semantic", "mapfile", "eval", "config", "system"]
FORBIDDEN = re.compile(r'#include\s*[<"](ros/|rclcpp|httplib|boost/beast|websocketpp|Q[A-Z]\w*|GL/|pangolin)')
INCLUDE = re.compile(r'#include\s*"sgslam/([a-z_]+)/')


def main():
    root = os.path.join(sys.argv[1] if len(sys.argv) > 1 else ".", "src", "sgslam")
    rank = {name: i for i, name in enumerate(LAYERS)}
    edges, problems = {}, []
    for folder in sorted(os.listdir(root)):
        path = os.path.join(root, folder)
        if not os.path.isdir(path):
            continue
        if folder not in rank:
            problems.append(f"src/sgslam/{folder}/: not in scripts/check_layers.py's LAYERS")
            continue
        for name in sorted(os.listdir(path)):
            file = os.path.join(path, name)
            for number, line in enumerate(open(file, encoding="utf-8"), 1):
                where = f"src/sgslam/{folder}/{name}:{number}"
                if FORBIDDEN.search(line):
                    problems.append(f"{where}: the core includes no ROS, HTTP or GUI header: {line.strip()}")
                m = INCLUDE.search(line)
                if not m or m.group(1) == folder:
                    continue
                target = m.group(1)
                edges.setdefault(folder, set()).add(target)
                if target not in rank or rank[target] > rank[folder]:
                    problems.append(f"{where}: {folder} may not include {target} (above it): {line.strip()}")
    for folder in LAYERS:
        print(f"{folder:9} -> {' '.join(sorted(edges.get(folder, ())))}")
    if problems:
        print("\n".join(["", "layering broken:"] + problems))
        return 1
    print("\nno folder includes one above it: no cycles")
    return 0


if __name__ == "__main__":
    sys.exit(main())
