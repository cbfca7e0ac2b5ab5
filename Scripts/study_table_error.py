"""Study 2 of issue 6: collision-table error against the exact distance to the mesh as the
table resolution grows, cylindrical and spherical, on the bundled head.

Run: pvpython Scripts/study_table_error.py <HairDynamics.so> <output dir> [--quick]

For n in 10, 20, 40, 80, 160 (--quick: 10, 20, 40) the Cylindrical Collision Map filter
builds an n x n table of the head (Data/body.vtk):
  spherical   frame of Data/body_parts.txt: origin (0, 1.555, 0.055), axis +Y, reference +Z,
              maximum radius 0.16 m;
  cylindrical vertical axis through (0, ., 0.055), heights 1.47-1.66 m, maximum radius 0.16 m.
At the samples the table's surface (output 1) lies on the mesh by construction, so the error
is measured where the table interpolates: at the centre of every quad of output 1 whose four
corners met the head and are not capped at the maximum radius (a capped sample is not
surface). The point measured is the quad's bilinear midpoint, the mean of its four corner
points. Its absolute distance to the input mesh is taken with VTK's
vtkImplicitPolyDataDistance (not HairDynamics code). As a cross-check the script also
measures the point the table's query uses at the cell centre: the mean of the four corner
radii along the cell-centre ray (printed and in the summary, not in the CSV).

Writes to the output dir: study_table_error.csv (projection, n, points, mean_mm, p95_mm,
max_mm), study_table_error.png (log-log, both projections, reference slope 2) and
study_table_error.txt (summary with the fitted slopes of log(mean error) against log(n)).
"""
import math
import os
import sys
import time

import numpy as np

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from paraview import servermanager  # noqa: E402
from paraview.simple import Delete, LegacyVTKReader, LoadPlugin, UpdatePipeline  # noqa: E402
from vtkmodules.util.numpy_support import vtk_to_numpy  # noqa: E402
from vtkmodules.vtkFiltersCore import vtkImplicitPolyDataDistance  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
MAX_RADIUS = 0.16
EXPECTED_SLOPE = 2.0

# name, filter properties, frame (origin, axis, reference) for rebuilding the rays
PROJECTIONS = [
    ("spherical",
     dict(Projection="Spherical", Origin=[0, 1.555, 0.055], Axis=[0, 1, 0],
          ReferenceDirection=[0, 0, 1], HeightRange=[0, 1], MaximumRadius=MAX_RADIUS)),
    ("cylindrical",
     dict(Projection="Cylindrical", Origin=[0, 0, 0.055], Axis=[0, 1, 0],
          ReferenceDirection=[0, 0, 1], HeightRange=[1.47, 1.66], MaximumRadius=MAX_RADIUS)),
]


def usage():
    sys.exit("usage: pvpython Scripts/study_table_error.py <HairDynamics.so> <output dir> [--quick]")


def fetch(proxy, port):
    return servermanager.Fetch(proxy, None, None, port)


def basis(props):
    """Columns e1 (reference made perpendicular to the axis), e2 = axis x e1, axis."""
    a = np.array(props["Axis"], float)
    a /= np.linalg.norm(a)
    r = np.array(props["ReferenceDirection"], float)
    e1 = r - (r @ a) * a
    e1 /= np.linalg.norm(e1)
    return e1, np.cross(a, e1), a


def ray(props, n, theta, second):
    """Origin and direction of the ray at table coordinates (theta, second) (arrays)."""
    e1, e2, a = basis(props)
    o = np.array(props["Origin"], float)
    c, s = np.cos(theta)[:, None], np.sin(theta)[:, None]
    if props["Projection"] == "Cylindrical":
        return o + second[:, None] * a, c * e1 + s * e2
    sp, cp = np.sin(second)[:, None], np.cos(second)[:, None]
    return np.broadcast_to(o, (len(theta), 3)), sp * (c * e1 + s * e2) + cp * a


def second_of(props, n, j):
    if props["Projection"] == "Cylindrical":
        h0, h1 = props["HeightRange"]
        return h0 + (h1 - h0) * j / (n - 1)
    return math.pi * j / (n - 1)


def distances(distance, points):
    """|distance| of each point (N x 3) to the mesh, through vtkImplicitPolyDataDistance."""
    out = np.empty(len(points))
    for k, p in enumerate(points):
        out[k] = abs(distance.EvaluateFunction(p[0], p[1], p[2]))
    return out


def measure(collision_map, body, distance, name, props, n):
    t0 = time.time()
    table = collision_map(Input=body, AutomaticFrame=0, Resolution=[n, n], **props)
    UpdatePipeline(proxy=table)
    surface = fetch(table, 1)
    build = time.time() - t0
    pts = vtk_to_numpy(surface.GetPoints().GetData()).astype(float)
    radius = vtk_to_numpy(surface.GetPointData().GetArray("Radius")).astype(float)
    check_layout(props, n, pts, radius)
    polys = vtk_to_numpy(surface.GetPolys().GetConnectivityArray()).astype(np.int64).reshape(-1, 4)
    # Only quads whose four corners are surface: none capped at the maximum radius. (Output 1
    # already holds only quads whose four corners met the mesh.)
    keep = np.all(radius[polys] < MAX_RADIUS - 1e-9, axis=1)
    quads = polys[keep]
    # 1. The bilinear midpoint of the quad (the mean of its four corners).
    mid = pts[quads].mean(axis=1)
    err = distances(distance, mid)
    # 2. Cross-check: the table's own surface at the cell centre, the mean radius along the
    #    cell-centre ray (what the query interpolates). Corner index s = j*n + i.
    i_lo = (quads % n).min(axis=1)
    i_hi = (quads % n).max(axis=1)
    wrap = (i_hi - i_lo) > 1  # the quad between i = n-1 and i = 0
    theta = 2 * math.pi * np.where(wrap, n - 0.5, i_lo + 0.5) / n
    j_lo = (quads // n).min(axis=1)
    second = second_of(props, n, j_lo + 0.5)
    o, d = ray(props, n, theta, second)
    on_ray = o + radius[quads].mean(axis=1)[:, None] * d
    err_ray = distances(distance, on_ray)
    row = dict(projection=name, n=n, points=len(err), mean_mm=1e3 * err.mean(),
               p95_mm=1e3 * np.percentile(err, 95), max_mm=1e3 * err.max(),
               ray_mean_mm=1e3 * err_ray.mean(), ray_p95_mm=1e3 * np.percentile(err_ray, 95),
               ray_max_mm=1e3 * err_ray.max(), over_2mm=int((err > 2e-3).sum()),
               median_mm=1e3 * np.median(err), quads=len(polys), capped_quads=int((~keep).sum()))
    print(f"{name:<12}{n:>5}{row['points']:>8}{row['mean_mm']:>10.4f}{row['p95_mm']:>10.4f}"
          f"{row['max_mm']:>10.3f}   ray: {row['ray_mean_mm']:>8.4f}{row['ray_p95_mm']:>9.4f}"
          f"{row['ray_max_mm']:>9.3f}   ({build:.1f} s build, {time.time() - t0:.1f} s total)",
          flush=True)
    Delete(table)
    return row


def check_layout(props, n, pts, radius):
    """The rays rebuilt here must give back output 1's points (index s = j*n + i)."""
    j, i = np.divmod(np.arange(n * n), n)
    o, d = ray(props, n, 2 * math.pi * i / n, second_of(props, n, j))
    gap = np.abs(o + radius[:, None] * d - pts).max()
    if gap > 1e-9:
        sys.exit(f"the rays rebuilt by the study miss output 1's points by {gap:.3g} m: "
                 "the table layout has changed")


def slope(ns, values):
    return float(np.polyfit(np.log(ns), np.log(values), 1)[0])


def main():
    args = [a for a in sys.argv[1:] if a != "--quick"]
    quick = "--quick" in sys.argv[1:]
    if len(args) != 2:
        usage()
    plugin, outdir = args
    if not os.path.exists(plugin):
        sys.exit(f"no plugin at {plugin}")
    os.makedirs(outdir, exist_ok=True)
    ns = [10, 20, 40] if quick else [10, 20, 40, 80, 160]

    LoadPlugin(plugin, remote=False, ns=globals())
    collision_map = globals()["CylindricalCollisionMap"]
    body = LegacyVTKReader(FileNames=[os.path.join(ROOT, "Data", "body.vtk")])
    UpdatePipeline(proxy=body)
    mesh = fetch(body, 0)
    distance = vtkImplicitPolyDataDistance()
    distance.SetInput(mesh)

    print(f"{'projection':<12}{'n':>5}{'points':>8}{'mean mm':>10}{'p95 mm':>10}{'max mm':>10}"
          f"   ray: mean, p95, max mm")
    rows = []
    for name, props in PROJECTIONS:
        for n in ns:
            rows.append(measure(collision_map, body, distance, name, props, n))

    with open(os.path.join(outdir, "study_table_error.csv"), "w") as f:
        f.write("projection,n,points,mean_mm,p95_mm,max_mm\n")
        for r in rows:
            f.write(f"{r['projection']},{r['n']},{r['points']},{r['mean_mm']:.6g},"
                    f"{r['p95_mm']:.6g},{r['max_mm']:.6g}\n")

    fits = {}
    for name, _ in PROJECTIONS:
        rs = [r for r in rows if r["projection"] == name]
        x = [r["n"] for r in rs]
        fits[name] = dict(mean=slope(x, [r["mean_mm"] for r in rs]),
                          p95=slope(x, [r["p95_mm"] for r in rs]),
                          max=slope(x, [r["max_mm"] for r in rs]),
                          ray_mean=slope(x, [r["ray_mean_mm"] for r in rs]),
                          median=slope(x, [r["median_mm"] for r in rs]))

    # --- plot ------------------------------------------------------------------------
    fig, ax = plt.subplots(figsize=(7, 5))
    colours = {"spherical": "tab:blue", "cylindrical": "tab:orange"}
    for name, _ in PROJECTIONS:
        rs = [r for r in rows if r["projection"] == name]
        x = np.array([r["n"] for r in rs], float)
        c = colours[name]
        ax.loglog(x, [r["mean_mm"] for r in rs], "o-", color=c,
                  label=f"{name}, mean (fitted slope {fits[name]['mean']:.2f})")
        ax.loglog(x, [r["p95_mm"] for r in rs], "s--", color=c, alpha=0.7, ms=4,
                  label=f"{name}, 95th percentile")
        ax.loglog(x, [r["max_mm"] for r in rs], "^:", color=c, alpha=0.5, ms=4,
                  label=f"{name}, max")
    x = np.array(ns, float)
    first = min(r["mean_mm"] for r in rows if r["n"] == ns[0])
    ax.loglog(x, 0.5 * first * (x / x[0]) ** -EXPECTED_SLOPE, "k-", lw=1,
              label="reference slope -2 (bilinear, smooth surface)")
    ax.set_xlabel("table resolution n (n x n samples)")
    ax.set_ylabel("distance of the interpolated surface to the mesh (mm)")
    ax.set_title("Collision-table error on the bundled head\n"
                 "(quad midpoints vs vtkImplicitPolyDataDistance)")
    ax.set_xticks(ns)
    ax.set_xticklabels([str(n) for n in ns])
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="lower left")
    fig.tight_layout()
    fig.savefig(os.path.join(outdir, "study_table_error.png"), dpi=120)

    # --- summary ---------------------------------------------------------------------
    lines = ["Collision-table error on the bundled head (Data/body.vtk)",
             f"resolutions n x n, n = {', '.join(map(str, ns))}" + (" (quick)" if quick else ""),
             "error: |distance| (vtkImplicitPolyDataDistance) of the bilinear midpoint of every",
             "quad of output 1 whose four corners are uncapped surface (Radius < 0.16 m)", ""]
    lines.append(f"{'projection':<12}{'n':>5}{'points':>8}{'mean mm':>10}{'p95 mm':>10}{'max mm':>10}"
                 f"{'median':>10}{'> 2 mm':>8}{'ray mean':>10}")
    for r in rows:
        lines.append(f"{r['projection']:<12}{r['n']:>5}{r['points']:>8}{r['mean_mm']:>10.4f}"
                     f"{r['p95_mm']:>10.4f}{r['max_mm']:>10.3f}{r['median_mm']:>10.4f}{r['over_2mm']:>8}"
                     f"{r['ray_mean_mm']:>10.4f}")
    lines.append("")
    lines.append("fitted order: -slope of log(error) against log(n), least squares over all n")
    for name, _ in PROJECTIONS:
        f_ = fits[name]
        lines.append(f"  {name:<12} mean {-f_['mean']:.2f} (expected {EXPECTED_SLOPE:.0f} for a smooth "
                     f"surface), median {-f_['median']:.2f}, p95 {-f_['p95']:.2f}, "
                     f"max {-f_['max']:.2f}; "
                     f"cell-centre ray mean {-f_['ray_mean']:.2f}")
    lines.append("  (the order is -slope: the slope of log(mean error) against log(n) itself is "
                 + ", ".join(f"{fits[nm]['mean']:.2f} {nm}" for nm, _ in PROJECTIONS) + ")")
    local = []
    for name, _ in PROJECTIONS:
        rs = [r for r in rows if r["projection"] == name]
        local.append(f"  {name:<12} " + ", ".join(
            f"{a['n']}->{b['n']}: {math.log(a['mean_mm'] / b['mean_mm']) / math.log(b['n'] / a['n']):.2f}"
            for a, b in zip(rs, rs[1:])))
    lines += ["local order of the mean between successive n:"] + local
    lines += ["'> 2 mm': quad midpoints farther than 2 mm from the mesh. From n = 40 on these are",
              "cells that bridge a jump of the radius (neighbouring rays keep different intervals,",
              "at the eyes, nose, ears and jaw): their error does not shrink with n, their number",
              "grows like n (a curve crosses n cells), so their share of the mean falls only like 1/n."]
    text = "\n".join(lines) + "\n"
    with open(os.path.join(outdir, "study_table_error.txt"), "w") as f:
        f.write(text)
    print()
    print(text, end="")


if __name__ == "__main__":
    main()
