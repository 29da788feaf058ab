#!/usr/bin/env python3
"""Copies a dataset with every frame cropped to a narrower horizontal and vertical field of view
around its principal point: the images (rgb, depth, occlusion, mask, mask_visib), cam_K in
scene_camera.json and the camera in scene_labels.json (width, height, cx, cy; fx and fy stay).
A frame whose field of view is already as narrow is copied whole; scene_gt.json and
scene_gt_info.json are copied unchanged (their boxes stay the whole frame's). What it is for: to measure
what a network trained at the paper's 60 deg would give on wider cameras if its input were the
60 deg view of theirs (doc/TRAINING.md, "Where the randomised IoU goes"). Prints the share of
occluded pixels the crops leave out, which the figures on the cropped copy cannot see.

Usage: scripts/crop_to_field_of_view.py DATASET OUT [--field-of-view-deg 60]
"""
import argparse
import glob
import json
import math
import os
import shutil
import sys

import numpy as np
from PIL import Image

from dataset_scenes import labelled_scenes

IMAGE_FOLDERS = ("rgb", "depth", "occlusion", "mask", "mask_visib")


def crop_window(camera, field_of_view_rad):
    """(x0, y0, width, height) of the frame's part within the field of view, inside the image."""
    half = math.tan(field_of_view_rad / 2.0)
    width = min(camera["width"], int(round(2.0 * camera["fx"] * half)))
    height = min(camera["height"], int(round(2.0 * camera["fy"] * half)))
    # Centred on the principal point (pixel centres at integers), kept inside the image.
    x0 = math.floor(camera["cx"] + 1.0 - width / 2.0)  # rounded half up
    y0 = math.floor(camera["cy"] + 1.0 - height / 2.0)
    x0 = max(0, min(camera["width"] - width, x0))
    y0 = max(0, min(camera["height"] - height, y0))
    return x0, y0, width, height


def main():
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dataset", help="a dataset folder whose labels record the camera")
    parser.add_argument("out", help="where the cropped copy goes; must not exist yet")
    parser.add_argument("--field-of-view-deg", type=float, default=60.0,
                        help="the horizontal and vertical field of view kept [deg] (default 60)")
    args = parser.parse_args()
    if not 0.0 < args.field_of_view_deg < 180.0:
        sys.exit("crop_to_field_of_view: the field of view must lie in (0, 180) deg")
    scenes = labelled_scenes("crop_to_field_of_view", args.dataset, args.out)
    field_of_view = math.radians(args.field_of_view_deg)

    os.makedirs(os.path.join(args.out, "train"))
    shutil.copy(os.path.join(args.dataset, "dataset.json"), args.out)
    kept = left_out = cropped = frames = 0
    for labels_path in scenes:
        scene = os.path.dirname(labels_path)
        out = os.path.join(args.out, "train", os.path.basename(scene))
        for folder in IMAGE_FOLDERS:
            os.makedirs(os.path.join(out, folder))
        with open(labels_path) as f:
            labels = json.load(f)
        with open(os.path.join(scene, "scene_camera.json")) as f:
            cameras = json.load(f)
        for key, label in labels.items():
            camera = label.get("camera")
            if camera is None:
                sys.exit("crop_to_field_of_view: %s: its labels do not record the camera" % scene)
            x0, y0, width, height = crop_window(camera, field_of_view)
            frames += 1
            cropped += (width, height) != (camera["width"], camera["height"])
            name = "%06d" % int(key)
            paths = [os.path.join(scene, folder, name + ".png")
                     for folder in ("rgb", "depth", "occlusion")]
            paths += glob.glob(os.path.join(scene, "mask*", name + "_*.png"))
            for path in paths:
                image = np.array(Image.open(path))
                if path.endswith(os.path.join("occlusion", name + ".png")):
                    occluded = image > 0
                    inside = int(occluded[y0:y0 + height, x0:x0 + width].sum())
                    kept += inside
                    left_out += int(occluded.sum()) - inside
                part = image[y0:y0 + height, x0:x0 + width]
                if part.dtype == np.int32:  # PIL reads 16-bit PNGs so; write them back 16-bit
                    part = part.astype(np.uint16)
                target = os.path.join(out, os.path.basename(os.path.dirname(path)),
                                      os.path.basename(path))
                Image.fromarray(part).save(target)
            camera.update(width=width, height=height, cx=camera["cx"] - x0,
                          cy=camera["cy"] - y0)
            matrix = cameras[key]["cam_K"]
            matrix[2] -= x0
            matrix[5] -= y0
        with open(os.path.join(out, "scene_labels.json"), "w") as f:
            json.dump(labels, f)
        with open(os.path.join(out, "scene_camera.json"), "w") as f:
            json.dump(cameras, f)
        for name in ("scene_gt.json", "scene_gt_info.json"):
            if os.path.exists(os.path.join(scene, name)):
                shutil.copy(os.path.join(scene, name), out)
    total = kept + left_out
    print("%d of %d frames cropped to %g deg; occluded pixels left out: %d of %d (%.2f %%)" %
          (cropped, frames, args.field_of_view_deg, left_out, total,
           100.0 * left_out / total if total else 0.0))


if __name__ == "__main__":
    main()
