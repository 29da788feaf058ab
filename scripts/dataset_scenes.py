"""What the scripts that read a dataset and write a new folder share (split_by_camera.py,
crop_to_field_of_view.py): the dataset checked, the output folder new, the scenes' labels."""
import glob
import os
import sys


def labelled_scenes(tool, dataset, out):
    """The scene_labels.json paths of `dataset`'s scenes, sorted; exits with `tool`'s message
    when `dataset` is not a dataset or has no labelled scene, or when `out` already exists."""
    if not os.path.isfile(os.path.join(dataset, "dataset.json")):
        sys.exit("%s: %s is not a dataset (no dataset.json)" % (tool, dataset))
    if os.path.exists(out):
        sys.exit("%s: %s exists; give a new folder" % (tool, out))
    scenes = sorted(glob.glob(os.path.join(dataset, "train", "*", "scene_labels.json")))
    if not scenes:
        sys.exit("%s: %s has no scene with labels" % (tool, dataset))
    return scenes
