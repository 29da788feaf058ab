#!/usr/bin/env python3
"""Splits a dataset's scenes into subsets by what the camera was (world, depth sensor, field of
view, image width, radius: the fields every label of a randomised set records), so that
`occlusion_train --check MODEL --data OUT/<group>` gives a model's figures per condition, e.g.
how its occlusion IoU on randomised frames falls with the field of view. A subset is a folder
with the dataset's dataset.json and, under train/, symbolic links to the scenes' folders (no
frame is copied; the dataset reader skips the scenes whose folder is absent); a scene's group is read from its first frame's labels, since the camera, world
and sensor are drawn per scene.

Usage: scripts/split_by_camera.py DATASET OUT --by KEY [--by KEY ...]
  KEY: world | depth_sensor | field_of_view | width | radius
  e.g. scripts/split_by_camera.py data/randomised runs/split --by field_of_view
       (groups fov_60-70, fov_70-80, fov_80-90 under runs/split)
"""
import argparse
import json
import math
import os
import sys

from dataset_scenes import labelled_scenes

KEYS = ("world", "depth_sensor", "field_of_view", "width", "radius")


def band(value, width, unit):
    """The band [k * width, (k + 1) * width) that holds value, as a name."""
    low = math.floor(value / width) * width
    return "%g-%g%s" % (low, low + width, unit)


def group_of(first_label, keys, args):
    camera = first_label.get("camera")
    parts = []
    for key in keys:
        if key in ("world", "depth_sensor"):
            if key not in first_label:
                raise ValueError("its labels do not record '%s'" % key)
            parts.append(first_label[key])
            continue
        if camera is None:
            raise ValueError("its labels do not record the camera (a dataset from before "
                             "camera randomisation)")
        if key == "field_of_view":
            parts.append("fov_" + band(math.degrees(camera["field_of_view_rad"]), args.fov_band,
                                       ""))
        elif key == "width":
            parts.append("width_" + band(camera["width"], args.width_band, "px"))
        else:
            parts.append("radius_" + band(camera["radius_m"], args.radius_band, "m"))
    return "_".join(parts)


def main():
    parser = argparse.ArgumentParser(
        description=__doc__.split("\n\n")[0],
        formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("dataset", help="a dataset folder (dataset.json, train/<scene>/...)")
    parser.add_argument("out", help="where the subsets go; must not exist yet")
    parser.add_argument("--by", action="append", choices=KEYS, required=True,
                        help="what to group the scenes by; several combine")
    parser.add_argument("--fov-band", type=float, default=10.0,
                        help="width of a field-of-view band [deg] (default 10)")
    parser.add_argument("--width-band", type=int, default=32,
                        help="width of an image-width band [px] (default 32)")
    parser.add_argument("--radius-band", type=float, default=0.25,
                        help="width of a radius band [m] (default 0.25)")
    args = parser.parse_args()
    if args.fov_band <= 0 or args.width_band <= 0 or args.radius_band <= 0:
        sys.exit("split_by_camera: band widths must be positive")

    scenes = labelled_scenes("split_by_camera", args.dataset, args.out)
    manifest = os.path.join(args.dataset, "dataset.json")

    groups = {}
    for labels_path in scenes:
        scene = os.path.dirname(labels_path)
        with open(labels_path) as f:
            labels = json.load(f)
        first = labels[min(labels, key=int)]
        try:
            name = group_of(first, args.by, args)
        except ValueError as error:
            sys.exit("split_by_camera: %s: %s" % (scene, error))
        groups.setdefault(name, []).append(scene)

    for name, members in sorted(groups.items()):
        train = os.path.join(args.out, name, "train")
        os.makedirs(train)
        with open(manifest) as source, open(os.path.join(args.out, name, "dataset.json"),
                                            "w") as copy:
            copy.write(source.read())
        for scene in members:
            # The same name under train/: the reader finds scenes by the manifest's indices and
            # skips those whose folder is absent, the other groups' scenes.
            os.symlink(os.path.abspath(scene), os.path.join(train, os.path.basename(scene)))
    print("| group | scenes | folder |")
    print("|---|---:|---|")
    for name, members in sorted(groups.items()):
        print("| %s | %d | %s |" % (name, len(members), os.path.join(args.out, name)))


if __name__ == "__main__":
    main()
