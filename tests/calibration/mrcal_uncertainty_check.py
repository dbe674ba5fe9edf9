#!/usr/bin/python3
"""Compares the projection-uncertainty map of a groundline intrinsics report
with mrcal's own, computed by Debian's python3-mrcal from the
optimization_inputs groundline writes into camera.cameramodel.

    tests/calibration/mrcal_uncertainty_check.py OUT_DIR

OUT_DIR is the --out of `groundline calibrate intrinsics` (camera.cameramodel
and report.json). Prints the largest and the median relative difference over
the report's map cells (cells groundline could not compute are skipped) and
exits 1 when the largest exceeds 10 %.
"""
import json
import sys

import mrcal
import numpy as np


def main(out_dir):
    model = mrcal.cameramodel(out_dir + "/camera.cameramodel")
    report = json.load(open(out_dir + "/report.json"))
    grid = report["projection_uncertainty"]["map"]
    cells_x, cells_y, range_m = grid["cells_x"], grid["cells_y"], grid["range_m"]
    width, height = model.imagersize()
    ours = np.array([np.nan if v is None else v for v in grid["worst_px"]]).reshape(cells_y, cells_x)
    relative = []
    for iy in range(cells_y):
        for ix in range(cells_x):
            # The cell centre, as UncertaintyMap::CellCentre.
            q = np.array(((ix + 0.5) * width / cells_x - 0.5, (iy + 0.5) * height / cells_y - 0.5))
            p = mrcal.unproject(q, *model.intrinsics(), normalize=True) * range_m
            theirs = mrcal.projection_uncertainty(p, model, what="worstdirection-stdev")
            relative.append(abs(ours[iy, ix] / theirs - 1.0))
    relative = np.array(relative)
    worst = np.nanmax(relative)
    print(f"{np.count_nonzero(~np.isnan(relative))} cells at {range_m} m: "
          f"max |groundline/mrcal - 1| = {worst:.2e}, median {np.nanmedian(relative):.2e}")
    return 0 if worst <= 0.1 else 1


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    sys.exit(main(sys.argv[1]))
