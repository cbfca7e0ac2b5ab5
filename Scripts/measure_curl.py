"""Curl of rendered hair against its guides, on the demo's curly Super-Helix run.

  pvpython Scripts/measure_curl.py <HairDynamics.so> Output
(after `bash Scripts/demo.sh`, which writes Output/super-helix-curly.h5). Prints, at t = 0
and 2.25 s, the mean curvature (mean turning angle per length) of the guides and of 2000
rendered strands of 161 points for both methods: the figures of docs/hair-interpolation.md.
"""
import os
import sys

import numpy as np
from paraview.simple import LegacyVTKReader, LoadPlugin
from vtkmodules.util.numpy_support import vtk_to_numpy
from vtkmodules.vtkCommonCore import vtkIdList

plugin, out = sys.argv[1], sys.argv[2]
LoadPlugin(plugin, remote=False, ns=globals())
here = os.path.dirname(os.path.abspath(__file__))
body = LegacyVTKReader(FileNames=[os.path.join(here, "..", "Data", "body.vtk")])
reader = HairStateReader(FileName=os.path.join(out, "super-helix-curly.h5"))  # noqa: F821


def mean_curvature(poly):
    pts = vtk_to_numpy(poly.GetPoints().GetData()).astype(float)
    ids, lines, per_strand = vtkIdList(), poly.GetLines(), []
    lines.InitTraversal()
    while lines.GetNextCell(ids):
        p = pts[[ids.GetId(i) for i in range(ids.GetNumberOfIds())]]
        a, b = np.diff(p, axis=0)[:-1], np.diff(p, axis=0)[1:]
        angle = np.arctan2(np.linalg.norm(np.cross(a, b), axis=1), (a * b).sum(1))
        per_strand.append((angle / (0.5 * (np.linalg.norm(a, axis=1) + np.linalg.norm(b, axis=1)))).mean())
    return np.mean(per_strand)


for t in (0.0, 2.25):
    reader.UpdatePipeline(t)
    guides = mean_curvature(reader.GetClientSideObject().GetOutputDataObject(0))
    for method in ("Semi-interpolation (Bertails et al.)", "Clusters (Kurihara et al.)"):
        hair = HairInterpolation(Input=reader, Scalp=body, NumberOfStrands=2000,  # noqa: F821
                                 PointsPerStrand=161, Method=method, Variation=0)
        hair.UpdatePipeline(t)
        rendered = mean_curvature(hair.GetClientSideObject().GetOutputDataObject(0))
        print(f"t = {t} s: guides {guides:.1f} 1/m, rendered ({method.split()[0]}) "
              f"{rendered:.1f} 1/m, ratio {rendered / guides:.3f}")
