#!/usr/bin/env python3
"""EuRoC ground truth -> (1) TUM body poses, times minus t0 [s] (t0: first IMU sample, as plucker vio
writes), (2) KITTI 3x4 T_w_c at each cam0 frame (nearest GT sample), T_w_c = T_w_b T_b_c."""
import sys, math
d = sys.argv[1]; out_tum = sys.argv[2]; out_kitti = sys.argv[3]
def rows(p):
    return [l.strip().split(',') for l in open(p) if l.strip() and not l.startswith('#')]
gt = [(int(r[0]), [float(x) for x in r[1:8]]) for r in rows(d + '/mav0/state_groundtruth_estimate0/data.csv')]
t0 = int(rows(d + '/mav0/imu0/data.csv')[0][0])
with open(out_tum, 'w') as f:
    for t, v in gt:
        p, q = v[:3], v[3:7]
        f.write('%.9f %.6f %.6f %.6f %.9f %.9f %.9f %.9f\n' % ((t - t0) * 1e-9, p[0], p[1], p[2], q[1], q[2], q[3], q[0]))
def R(q):
    w, x, y, z = q
    return [[1-2*(y*y+z*z), 2*(x*y-w*z), 2*(x*z+w*y)], [2*(x*y+w*z), 1-2*(x*x+z*z), 2*(y*z-w*x)], [2*(x*z-w*y), 2*(y*z+w*x), 1-2*(x*x+y*y)]]
ys = open(d + '/mav0/cam0/sensor.yaml').read()
data = ys[ys.index('data:'):]; data = data[data.index('[')+1:data.index(']')]
T = [float(x) for x in data.replace('\n', ' ').split(',')]
Rbc = [T[0:3], T[4:7], T[8:11]]; tbc = [T[3], T[7], T[11]]
cams = [int(r[0]) for r in rows(d + '/mav0/cam0/data.csv')]
import bisect
ts = [g[0] for g in gt]
with open(out_kitti, 'w') as f:
    for tc in cams:
        i = bisect.bisect_left(ts, tc)
        i = min(range(max(i-1, 0), min(i+1, len(ts)-1)+1), key=lambda k: abs(ts[k]-tc))
        v = gt[i][1]; Rwb = R(v[3:7]); p = v[:3]
        Rwc = [[sum(Rwb[a][k]*Rbc[k][b] for k in range(3)) for b in range(3)] for a in range(3)]
        pc = [p[a] + sum(Rwb[a][k]*tbc[k] for k in range(3)) for a in range(3)]
        f.write(' '.join('%.9f' % x for x in (Rwc[0] + [pc[0]] + Rwc[1] + [pc[1]] + Rwc[2] + [pc[2]])) + '\n')
