#!/usr/bin/env python3
"""Every include runs down the layers, never up: the hub's layers in the order of
MOCAP_HUB_LAYERS (hub/CMakeLists.txt) and the firmware's modules in the order of
MOCAP_FIRMWARE_MODULES (firmware/CMakeLists.txt). A file may include its own layer and any layer
listed before it. Prints each include that runs up (file:line, its layer, the included layer)
and exits 1 when there is one; also fails when a source folder is missing from the order.

usage: tests/house/check_layers.py [SOURCE_ROOT]"""

import os
import re
import sys

INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"/]+)/[^"]+"')


def layer_order(cmake_file, variable):
    text = open(cmake_file, encoding="utf-8").read()
    found = re.search(r'set\(%s\s+"([^"]+)"' % variable, text)
    if not found:
        sys.exit("%s: no %s list" % (cmake_file, variable))
    return found.group(1).split(";")


def check_tree(root, order, what):
    """The includes under ROOT/<layer>/ that run up ORDER; folders not in ORDER."""
    rank = {layer: i for i, layer in enumerate(order)}
    problems = []
    for layer in sorted(os.listdir(root)):
        folder = os.path.join(root, layer)
        if not os.path.isdir(folder):
            continue
        if layer not in rank:
            problems.append("%s: folder %s is not in the %s order %s" % (folder, layer, what, order))
            continue
        for dirpath, _, files in os.walk(folder):
            for name in sorted(files):
                if not name.endswith((".h", ".c", ".cc")):
                    continue
                path = os.path.join(dirpath, name)
                with open(path, encoding="utf-8", errors="replace") as source:
                    for number, line in enumerate(source, 1):
                        match = INCLUDE.match(line)
                        if match and match.group(1) in rank and rank[match.group(1)] > rank[layer]:
                            problems.append("%s:%d: %s layer %s includes %s, above it" %
                                            (path, number, what, layer, match.group(0).strip()))
    return problems


def main():
    root = sys.argv[1] if len(sys.argv) > 1 else os.path.join(os.path.dirname(__file__), "..", "..")
    hub = layer_order(os.path.join(root, "hub", "CMakeLists.txt"), "MOCAP_HUB_LAYERS")
    firmware = layer_order(os.path.join(root, "firmware", "CMakeLists.txt"), "MOCAP_FIRMWARE_MODULES")
    problems = check_tree(os.path.join(root, "hub", "src"), hub, "hub") + \
        check_tree(os.path.join(root, "firmware"), firmware, "firmware")
    for problem in problems:
        print(problem)
    print("hub layers: %s\nfirmware modules: %s\n%d include(s) running up the layers" %
          (" < ".join(hub), " < ".join(firmware), len(problems)))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())
