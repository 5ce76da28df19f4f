"""Facts about compare_mesh2's measurements on one shared polygon with holes.

usage: check_compare_mesh2.py COMPARE_MESH2 SHARED_DATA_DIR

dude.json has two holes: CGAL's mesh covers the domain (outer ring minus holes) only when
a seed lands in each hole, so its coverage must be 1 (sum of triangle areas against the
area of the domain, computed here exactly with fractions); voroclip's mesh must pass
check_mesh2 and lie inside; the vertex counts must be within 10 %. A polygon with touching
rings must give exit status 1 and a one-line error naming the file, a bad option exit 2.
"""
import json
import subprocess
import sys
from fractions import Fraction


def ring_area(ring):
    pts = [(Fraction(x), Fraction(y)) for x, y in ring]
    if pts[0] == pts[-1]:
        pts.pop()
    return sum(pts[i][0] * pts[(i + 1) % len(pts)][1] - pts[(i + 1) % len(pts)][0] * pts[i][1]
               for i in range(len(pts))) / 2


def main():
    exe, data = sys.argv[1], sys.argv[2]
    failures = []

    def check(ok, what):
        if not ok:
            failures.append(what)

    polygon = f"{data}/polygons/valid/dude.json"
    run = subprocess.run([exe, "--polygon", polygon, "--vertices", "300", "--runs", "1",
                          "--json"], capture_output=True, text=True, timeout=600)
    check(run.returncode == 0, f"exit status {run.returncode}: {run.stderr[-500:]}")
    result = json.loads(run.stdout)
    check(len(result["polygons"]) == 1, "one polygon")
    p = result["polygons"][0]
    check(p["polygon"] == "dude" and p["error"] == "", f"polygon row: {p['polygon']} {p['error']}")
    rows = {m["mesher"]: m for m in p["meshers"]}
    check(sorted(rows) == ["CGAL", "voroclip"], f"meshers {sorted(rows)}")

    # The domain's area, exactly: |outer| - sum |holes|.
    with open(polygon) as f:
        rings = json.load(f)
    area = abs(ring_area(rings[0])) - sum(abs(ring_area(r)) for r in rings[1:])
    check(area > 0, "positive area")

    cgal, ours = rows["CGAL"], rows["voroclip"]
    # The holes are left out (seeds) and the rest is covered: coverage 1 up to rounding.
    check(abs(cgal["coverage"] - 1) < 1e-9, f"CGAL coverage {cgal['coverage']!r}")
    for name, m in rows.items():
        check(m["triangles_outside"] == 0, f"{name}: {m['triangles_outside']} triangles outside")
        check(0 < m["min_angle_deg"] <= m["mean_min_angle_deg"] <= 60,
              f"{name}: angles {m['min_angle_deg']} {m['mean_min_angle_deg']}")
        # Euler: a triangulated disk with h holes has T = 2 V - B - 2 + 2 h triangles, B
        # boundary vertices (B >= the polygon's vertices); so T < 2 V.
        check(0 < m["triangles"] < 2 * m["vertices"], f"{name}: {m['triangles']} triangles")
        check(m["wall_seconds"] > 0 and m["cpu_seconds"] > 0, f"{name}: times")
    check(ours["check_mesh2"] == "", f"voroclip check_mesh2: {ours['check_mesh2']}")
    check(0.9 < ours["coverage"] <= 1 + 1e-12, f"voroclip coverage {ours['coverage']!r}")
    check(abs(ours["vertices"] - cgal["vertices"]) <= 0.1 * cgal["vertices"],
          f"vertex counts {ours['vertices']} / {cgal['vertices']}")

    # The table (default output) has one row per mesher with the same figures.
    table = subprocess.run([exe, "--polygon", polygon, "--vertices", "300", "--runs", "1"],
                           capture_output=True, text=True, timeout=600)
    table_rows = [line for line in table.stdout.splitlines() if line.startswith("| dude |")]
    check(len(table_rows) == 2, f"table rows: {table_rows}")
    for line in table_rows:
        cells = [c.strip() for c in line.strip("|").split("|")]
        m = rows[cells[1]]
        check(int(cells[2]) == m["vertices"] and int(cells[3]) == m["triangles"],
              f"table row {cells[:4]} against the JSON")

    bad = f"{data}/polygons/degenerate/self-touching.json"
    run = subprocess.run([exe, "--polygon", bad, "--json"], capture_output=True, text=True,
                         timeout=600)
    check(run.returncode == 1, f"bad polygon: exit status {run.returncode}")
    errors = [line for line in run.stderr.splitlines() if line.startswith("compare_mesh2:")]
    check(len(errors) == 1 and "self-touching.json" in errors[0], f"bad polygon: {errors}")
    check(json.loads(run.stdout)["polygons"][0]["error"] != "", "bad polygon: error in JSON")

    run = subprocess.run([exe, "--no-such-option"], capture_output=True, text=True, timeout=60)
    check(run.returncode == 2 and "usage" in run.stderr, f"bad option: {run.returncode}")

    for f in failures:
        print("FAILED:", f)
    print(f"domain area {float(area):.17g}; CGAL {cgal['vertices']} vertices, voroclip "
          f"{ours['vertices']}; {len(failures)} failure(s)")
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())
