#!/usr/bin/env python3
"""How well two renders of a scene agree in outline (make bench-bigmesh):

  outline_agree.py A.png B.png

Prints |A ∩ B| / |A ∪ B| of the pixels that are not background in each,
the background being each image's top-left pixel (to within 24 of 765 in
the sum of the channels' differences): 1 means the same silhouette, so
the same camera and the same mesh; a peer's image that is mirrored,
shifted or scaled scores far lower."""
import sys

import numpy as np
from PIL import Image


def mask(path):
    a = np.asarray(Image.open(path).convert("RGB")).astype(np.int32)
    return np.abs(a - a[0, 0]).sum(axis=-1) > 24


a, b = mask(sys.argv[1]), mask(sys.argv[2])
if a.shape != b.shape:
    print("sizes differ")
else:
    print("%.3f" % ((a & b).sum() / max((a | b).sum(), 1)))
