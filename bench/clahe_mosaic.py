"""The CLAHE benchmark's 1024 x 1024 photograph: skimage's brick, grass,
gravel and camera (512 x 512 each), two by two, as an 8-bit grey PNG.
  clahe_mosaic.py SKIMAGE_DATA_DIR OUT.png"""
import sys

import cv2
import numpy as np

d, out = sys.argv[1], sys.argv[2]
tiles = [cv2.imread("%s/%s.png" % (d, n), cv2.IMREAD_GRAYSCALE) for n in ("brick", "grass", "gravel", "camera")]
cv2.imwrite(out, np.vstack([np.hstack(tiles[:2]), np.hstack(tiles[2:])]))
