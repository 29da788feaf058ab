#!/usr/bin/env python3
"""How much of a dataset's depth the sensor did not read: the share of all pixels, and of the
occlusion label's pixels, whose depth is 0 (no reading; doc/TRAINING.md, "Training data"), over
every frame of each dataset given. An occluded pixel lies behind a nearer object, so where the
nearer object is inside a sensor's minimum range it has no depth: the network must find that
occlusion from colour alone.

Usage: scripts/depth_coverage.py DATASET [DATASET ...]
  e.g. scripts/depth_coverage.py runs/check_room_ideal runs/check_room_azure_kinect
"""
import argparse
import sys
from pathlib import Path

import numpy as np
from PIL import Image


def coverage(dataset):
    """(frames, share of pixels without depth, share of occluded pixels without depth)."""
    frames = pixels = unread = occluded = occluded_unread = 0
    for depth_png in sorted(Path(dataset).glob("train/*/depth/*.png")):
        depth = np.asarray(Image.open(depth_png))
        label = np.asarray(Image.open(depth_png.parent.parent / "occlusion" / depth_png.name)) > 0
        if label.ndim == 3:
            label = label.any(axis=-1)
        no_reading = depth == 0
        frames += 1
        pixels += depth.size
        unread += int(no_reading.sum())
        occluded += int(label.sum())
        occluded_unread += int((no_reading & label).sum())
    if frames == 0:
        sys.exit("depth_coverage: no frames under %s/train/*/depth/" % dataset)
    return frames, unread / pixels, occluded_unread / occluded if occluded else float("nan")


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("datasets", nargs="+", metavar="DATASET", help="occlusion_dataset --out")
    args = parser.parse_args()
    rows = [(dataset,) + coverage(dataset) for dataset in args.datasets]
    print("| dataset | frames | no depth, all pixels | no depth, occluded pixels |")
    print("|---|---:|---:|---:|")
    for dataset, frames, all_share, occluded_share in rows:
        print("| %s | %d | %.1f %% | %.1f %% |" % (dataset, frames, 100 * all_share,
                                                  100 * occluded_share))


if __name__ == "__main__":
    main()
