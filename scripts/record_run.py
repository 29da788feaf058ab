#!/usr/bin/env python3
"""Records a finished occlusion_train run in doc/training: its best model's manifest with the
command that made it, the sha256 of its datasets' manifests (and of the model it started from,
for a warm restart), and the run's length, wall time and speed; its log and curves beside it.

Usage: scripts/record_run.py RUN_DIR OUT_STEM COMMAND
  writes OUT_STEM.json, OUT_STEM.csv (RUN_DIR/log.csv) and OUT_STEM.png (RUN_DIR/curves.png).
Paths in the manifests are relative to the source tree: run it from there (train_table3.sh does).
"""
import csv
import hashlib
import json
import os
import shutil
import statistics
import sys


def sha256(path):
    with open(path, "rb") as f:
        return hashlib.sha256(f.read()).hexdigest()


def log_of(run):
    with open(os.path.join(run, "log.csv")) as f:
        return list(csv.DictReader(f))


def main():
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    run, out_stem, command = sys.argv[1:]
    with open(os.path.join(run, "best.json")) as f:
        manifest = json.load(f)
    epochs = log_of(run)
    manifest["command"] = command
    digest = lambda d: sha256(os.path.join(d, "dataset.json"))
    manifest["dataset_manifest_sha256"] = digest(manifest["dataset"])
    if "extra_datasets" in manifest:
        manifest["extra_dataset_manifest_sha256"] = [digest(d) for d in manifest["extra_datasets"]]
    if "initialised_from" in manifest:
        start = manifest["initialised_from"]
        start["sha256"] = sha256(start["model"])
        # What the starting weights went through: the epochs (and training images) up to each
        # best model along the chain of warm restarts, and the wall time of those runs (from
        # their logs).
        epochs_before, images_before, minutes_before = 0, 0, 0.0
        model = start["model"]
        while model:
            with open(os.path.splitext(model)[0] + ".json") as f:
                earlier = json.load(f)
            epochs_before += earlier["epoch"]
            images_before += earlier["epoch"] * earlier["train_frames"]
            minutes_before += sum(float(e["seconds"]) for e in log_of(os.path.dirname(model))) / 60
            model = earlier.get("initialised_from", {}).get("model")
        start["epochs_before"] = epochs_before
        start["images_before"] = images_before
        start["run"] = {"minutes": minutes_before}
    # The whole run: its length, wall time and speed (the best epoch's figures are "validation").
    manifest["run"] = {
        "epochs": len(epochs),
        "minutes": sum(float(e["seconds"]) for e in epochs) / 60.0,
        "median_images_per_second": statistics.median(
            float(e["images_per_second"]) for e in epochs),
    }
    with open(out_stem + ".json", "w") as f:
        json.dump(manifest, f, indent=2)
    shutil.copyfile(os.path.join(run, "log.csv"), out_stem + ".csv")
    if os.path.exists(os.path.join(run, "curves.png")):
        shutil.copyfile(os.path.join(run, "curves.png"), out_stem + ".png")


if __name__ == "__main__":
    main()
