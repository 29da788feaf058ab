#!/usr/bin/env python3
"""Ships a model derived from a shipped one without training: the same weights (copied) with
network fields of its manifest changed, e.g. how missing depth enters (depth_gaps, doc/TRAINING.md
"Training for real cameras"). The new manifest records what it was derived from (file and sha256)
and the command; models/MANIFEST.md lists it by hand with its figures and their commands.

Usage: scripts/derive_model.py SOURCE.pt NAME FIELD=VALUE [FIELD=VALUE ...]
  e.g. scripts/derive_model.py models/multitask_unet64.pt multitask_unet64_camera depth_gaps=filled
"""
import hashlib
import json
import os
import shutil
import sys


def sha256(path):
    digest = hashlib.sha256()
    with open(path, "rb") as stream:
        for block in iter(lambda: stream.read(1 << 20), b""):
            digest.update(block)
    return digest.hexdigest()


def number_or_text(value):
    try:
        return int(value)
    except ValueError:
        pass
    try:
        return float(value)
    except ValueError:
        return value


def main(argv):
    if len(argv) < 4 or any("=" not in a for a in argv[3:]):
        sys.exit(__doc__)
    source, name = argv[1], argv[2]
    # A number enters the manifest as a number (view_crop=0.5), anything else as text (far).
    changes = {k: number_or_text(v) for k, v in (a.split("=", 1) for a in argv[3:])}
    source_json = os.path.splitext(source)[0] + ".json"
    if not (os.path.isfile(source) and os.path.isfile(source_json)):
        sys.exit(f"derive_model: {source} or its manifest {source_json} is missing")
    manifest = json.load(open(source_json))
    # Fields that older manifests lack (their defaults: far, kept, metres, 1, 0).
    unknown = [f for f in changes if f not in manifest["network"]
               and f not in ("depth_gaps", "bounding_surfaces", "depth_reference", "view_crop",
                             "view_field_of_view")]
    if unknown:
        sys.exit(f"derive_model: no network field {', '.join(unknown)} in {source_json}")
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    target = os.path.join(root, "models", name + ".pt")
    shutil.copyfile(source, target)
    manifest["network"].update(changes)
    # manifest["training"]["network"] stays the source's: the network the weights were trained as.
    manifest["file"] = name + ".pt"
    manifest["derived_from"] = {"file": os.path.basename(source), "sha256": sha256(source),
                                "changed": changes, "weights": "unchanged"}
    manifest["command"] = "scripts/derive_model.py " + " ".join(argv[1:])
    with open(os.path.splitext(target)[0] + ".json", "w") as stream:
        json.dump(manifest, stream, indent=2, sort_keys=False)
        stream.write("\n")
    print(f"{target}: sha256 {sha256(target)}")


if __name__ == "__main__":
    main(sys.argv)
