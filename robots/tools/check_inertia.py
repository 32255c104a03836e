#!/usr/bin/env python3
"""Sanity checks for the sweepgen URDFs (pure Python, no dependencies).

For every <link> with an <inertial>:
  * mass > 0
  * the inertia tensor (about the COM) is positive definite
    (Sylvester's criterion and principal moments > 0)
  * triangle inequalities hold, both for the diagonal entries as written and
    for the principal moments (Ia + Ib >= Ic for every permutation)
For every revolute/prismatic joint: <limit> has lower, upper, effort, velocity,
with lower < upper and effort, velocity > 0.
Every origin rpy value that is within 1e-3 of a multiple of pi/4 must be the
full double-precision value (e.g. 1.5707963267948966, not 1.5708).

Usage: check_inertia.py [file.urdf ...]   (default: every robots/**/*.urdf)
Exit status 0 if all checks pass.
"""
import glob
import math
import os
import sys
import xml.etree.ElementTree as ET

TOL = 1e-12


def eig_sym3(a):
    """Eigenvalues of a symmetric 3x3 matrix (closed form, ascending)."""
    p1 = a[0][1] ** 2 + a[0][2] ** 2 + a[1][2] ** 2
    q = (a[0][0] + a[1][1] + a[2][2]) / 3.0
    if p1 == 0.0:
        return sorted([a[0][0], a[1][1], a[2][2]])
    p2 = sum((a[i][i] - q) ** 2 for i in range(3)) + 2.0 * p1
    p = math.sqrt(p2 / 6.0)
    b = [[(a[i][j] - (q if i == j else 0.0)) / p for j in range(3)] for i in range(3)]
    detb = (b[0][0] * (b[1][1] * b[2][2] - b[1][2] * b[2][1])
            - b[0][1] * (b[1][0] * b[2][2] - b[1][2] * b[2][0])
            + b[0][2] * (b[1][0] * b[2][1] - b[1][1] * b[2][0]))
    r = max(-1.0, min(1.0, detb / 2.0))
    phi = math.acos(r) / 3.0
    e1 = q + 2.0 * p * math.cos(phi)
    e3 = q + 2.0 * p * math.cos(phi + 2.0 * math.pi / 3.0)
    e2 = 3.0 * q - e1 - e3
    return sorted([e1, e2, e3])


def triangle_ok(x, y, z):
    s = max(abs(x), abs(y), abs(z))
    return x + y >= z - TOL * s and y + z >= x - TOL * s and x + z >= y - TOL * s


def check_file(path):
    errors = []
    rows = []
    root = ET.parse(path).getroot()
    for link in root.findall('link'):
        name = link.get('name')
        inert = link.find('inertial')
        if inert is None:
            rows.append((name, None))
            continue
        m = float(inert.find('mass').get('value'))
        i = inert.find('inertia')
        g = {k: float(i.get(k)) for k in ('ixx', 'ixy', 'ixz', 'iyy', 'iyz', 'izz')}
        I = [[g['ixx'], g['ixy'], g['ixz']],
             [g['ixy'], g['iyy'], g['iyz']],
             [g['ixz'], g['iyz'], g['izz']]]
        m1 = I[0][0]
        m2 = I[0][0] * I[1][1] - I[0][1] ** 2
        m3 = (I[0][0] * (I[1][1] * I[2][2] - I[1][2] ** 2)
              - I[0][1] * (I[0][1] * I[2][2] - I[1][2] * I[0][2])
              + I[0][2] * (I[0][1] * I[1][2] - I[1][1] * I[0][2]))
        ev = eig_sym3(I)
        pd = m1 > 0 and m2 > 0 and m3 > 0 and ev[0] > 0
        tri_diag = triangle_ok(g['ixx'], g['iyy'], g['izz'])
        tri_princ = triangle_ok(*ev)
        if m <= 0:
            errors.append(f'{name}: mass {m} <= 0')
        if not pd:
            errors.append(f'{name}: inertia not positive definite (eig {ev})')
        if not tri_diag:
            errors.append(f'{name}: diagonal violates triangle inequality')
        if not tri_princ:
            errors.append(f'{name}: principal moments violate triangle inequality {ev}')
        # slack of the tightest principal triangle inequality, relative
        slack = min(ev[0] + ev[1] - ev[2], ev[1] + ev[2] - ev[0], ev[0] + ev[2] - ev[1]) / ev[2]
        rows.append((name, (m, ev, pd, tri_diag, tri_princ, slack)))
    for j in root.findall('joint'):
        jt = j.get('type')
        o = j.find('origin')
        if o is not None and o.get('rpy'):
            for s in o.get('rpy').split():
                v = float(s)
                k = round(v / (math.pi / 4))
                if abs(v - k * math.pi / 4) < 1e-3 and float(repr(k * math.pi / 4)) != v:
                    errors.append(f'joint {j.get("name")}: rpy {s} is not full precision')
        if jt in ('revolute', 'prismatic'):
            lim = j.find('limit')
            if lim is None or any(lim.get(a) is None for a in ('lower', 'upper', 'effort', 'velocity')):
                errors.append(f'joint {j.get("name")}: incomplete <limit>')
                continue
            lo, hi = float(lim.get('lower')), float(lim.get('upper'))
            ef, ve = float(lim.get('effort')), float(lim.get('velocity'))
            if not (lo < hi and ef > 0 and ve > 0):
                errors.append(f'joint {j.get("name")}: bad limit values')
    return rows, errors


def main(argv):
    here = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    files = argv[1:] or sorted(glob.glob(os.path.join(here, '**', '*.urdf'), recursive=True))
    bad = 0
    for f in files:
        rows, errors = check_file(f)
        print(f'== {os.path.relpath(f, here)}')
        for name, r in rows:
            if r is None:
                print(f'   {name:18s} (no inertial: massless frame)')
                continue
            m, ev, pd, td, tp, slack = r
            print(f'   {name:18s} m={m:<9g} principal=({ev[0]:.4g}, {ev[1]:.4g}, {ev[2]:.4g}) '
                  f'PD={"ok" if pd else "FAIL"} tri(diag)={"ok" if td else "FAIL"} '
                  f'tri(principal)={"ok" if tp else "FAIL"} min slack={slack:.3g}')
        for e in errors:
            print('   ERROR:', e)
        bad += len(errors)
    print('ALL CHECKS PASSED' if bad == 0 else f'{bad} ERROR(S)')
    return 0 if bad == 0 else 1


if __name__ == '__main__':
    sys.exit(main(sys.argv))
