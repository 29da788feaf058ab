#!/usr/bin/python3
"""One scene clean, in a room, and through each depth sensor: doc/images/world_sensors.png.

Runs occlusion_render five times (seed 5, 256 px) and puts the colour images over the
colourised depth images (black = no depth reading).
Usage: scripts/world_sensor_montage.py [BUILD_WS] [OUT_PNG]
"""
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np
from PIL import Image, ImageDraw

WS = Path(sys.argv[1] if len(sys.argv) > 1 else ".build_ws")
OUT = Path(sys.argv[2] if len(sys.argv) > 2 else "doc/images/world_sensors.png")
RENDER = WS / "devel/lib/occlusion_env/occlusion_render"
VIEWS = [("void", "ideal"), ("room", "ideal"), ("room", "kinect_v1"),
         ("room", "realsense_d435"), ("room", "azure_kinect")]


def main():
    tiles = []
    with tempfile.TemporaryDirectory() as tmp:
        for world, sensor in VIEWS:
            out = Path(tmp) / f"{world}_{sensor}"
            subprocess.run([str(RENDER), "--seed", "5", "--world", world, "--depth-sensor", sensor,
                            "--out", str(out)], check=True, stdout=subprocess.DEVNULL)
            rgb = np.asarray(Image.open(out / "rgb.png").convert("RGB"))
            depth = np.asarray(Image.open(out / "depth.png").convert("RGB"))
            column = np.concatenate([rgb, depth], axis=0)
            tile = Image.fromarray(column)
            ImageDraw.Draw(tile).text((4, 4), f"{world} / {sensor}", fill=(255, 255, 0))
            tiles.append(np.asarray(tile))
    OUT.parent.mkdir(parents=True, exist_ok=True)
    Image.fromarray(np.concatenate(tiles, axis=1)).save(OUT, optimize=True)
    print("wrote", OUT)


if __name__ == "__main__":
    main()
