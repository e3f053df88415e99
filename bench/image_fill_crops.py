#!/usr/bin/env python3
"""The hole's neighbourhood, side by side, from a bench/image_fill.sh run:
input (the hole in magenta), relief's default, relief --method jain,
PatchMatch, Resynthesizer, the truth; each panel the hole's bounding box
grown by 16 pixels, scaled to 160 pixels high, labelled. For the docs:
smaller than the whole strips --figures writes, and the seams show.
  bench/image_fill_crops.py OUT_DIR IMAGES_DIR FIGURES_DIR IMAGE_HOLE...
(e.g. chelsea_rect_off), run in bench/.venv-image (OpenCV)."""
import glob
import os
import sys

import cv2
import numpy as np

PANELS = [("input", None), ("relief default", "relief_default"),
          ("relief jain", "relief_jain"), ("patchmatch", "patchmatch"),
          ("resynthesizer", "resynthesizer"), ("truth", "")]


def colour(img):
    return cv2.cvtColor(img, cv2.COLOR_GRAY2BGR) if img.ndim == 2 else img[:, :, :3]


def panel(img, label, height=160):
    s = height / img.shape[0]
    img = cv2.resize(img, (max(1, round(img.shape[1] * s)), height),
                     interpolation=cv2.INTER_NEAREST if s >= 1 else cv2.INTER_AREA)
    bar = np.full((18, img.shape[1], 3), 255, np.uint8)
    cv2.putText(bar, label, (3, 13), cv2.FONT_HERSHEY_SIMPLEX, 0.42, (0, 0, 0), 1, cv2.LINE_AA)
    return np.pad(np.vstack([bar, img]), ((0, 0), (0, 4), (0, 0)), constant_values=255)


def main():
    out, images, figures = sys.argv[1:4]
    os.makedirs(figures, exist_ok=True)
    for key in sys.argv[4:]:
        stem = key.split("_")[0]
        truth = colour(cv2.imread(glob.glob(os.path.join(images, stem + ".*"))[0],
                                  cv2.IMREAD_UNCHANGED))
        mask = cv2.imread(os.path.join(out, key + "_mask.png"), 0) > 0
        ys, xs = np.nonzero(mask)
        y0, y1 = max(ys.min() - 16, 0), min(ys.max() + 17, truth.shape[0])
        x0, x1 = max(xs.min() - 16, 0), min(xs.max() + 17, truth.shape[1])
        row = []
        for label, name in PANELS:
            if name is None:
                img = truth.copy()
                img[mask] = (255, 0, 255)
            elif name == "":
                img = truth
            else:
                img = colour(cv2.imread(os.path.join(out, "%s_%s.png" % (key, name)),
                                        cv2.IMREAD_UNCHANGED))
            row.append(panel(img[y0:y1, x0:x1], label))
        path = os.path.join(figures, "image_fill_%s.png" % key)
        cv2.imwrite(path, np.hstack(row), [cv2.IMWRITE_PNG_COMPRESSION, 9])
        print(path)


if __name__ == "__main__":
    main()
