"""OpenCV's CLAHE (cv2.createCLAHE, one thread) on the same image as
bench/clahe_bench.c, timed the same way, and compared pixel by pixel with
sumi's output:
  clahe_opencv.py IMAGE TILES_X TILES_Y CLIP SUMI.raw
prints: opencv_ms max_diff pixels_differing"""
import statistics
import sys
import time

import cv2
import numpy as np

RUNS = 21


def main():
    path, tx, ty, clip, mine = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4]), sys.argv[5]
    cv2.setNumThreads(1)
    cv2.ocl.setUseOpenCL(False)
    img = cv2.imread(path, cv2.IMREAD_GRAYSCALE)
    clahe = cv2.createCLAHE(clipLimit=clip, tileGridSize=(tx, ty))
    out = clahe.apply(img)   # warm-up
    times = []
    for _ in range(RUNS):
        t0 = time.perf_counter()
        out = clahe.apply(img)
        times.append((time.perf_counter() - t0) * 1000)
    ours = np.fromfile(mine, np.uint8).reshape(img.shape)
    diff = np.abs(ours.astype(int) - out.astype(int))
    print("%.3f %d %d" % (statistics.median(times), diff.max(), int((diff > 0).sum())))


main()
