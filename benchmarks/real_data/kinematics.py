"""A URDF arm with an error on every joint, in numpy: the benchmark scripts' own forward
kinematics and first derivatives (no kincal code). The error model is the one kincal's
`urdf-arm` documents (docs/theory.md, "Arms imported from a URDF"):

    T(q) = B . prod_i [ C_i . E_i . M_i(q_i + o_i) ] . C_tip . T_tool

B (`base.*`), E_i (`<joint>.origin.*`) and T_tool (`tool.*`) are frame blocks: a position
(mm) and Z-Y-X angles (rad), R = Rz(rz) Ry(ry) Rx(rx), all 0 nominally. C_i is joint i's URDF
origin composed with the fixed joints before it, C_tip the fixed joints after the last moving
one, M_i the joint's turn about (or slide along) its axis by the joint value plus its offset
o_i (`<joint>.offset`).

Every parameter moves the end frame by an elementary motion in base coordinates, which is all
a Jacobian column needs: a translation along u, or a turn about the unit axis u through the
point o. `walk` returns the end frame and these motions for all rows at once.
"""

import math
import xml.etree.ElementTree as ET

import numpy as np

FRAME = ("x", "y", "z", "rx", "ry", "rz")


def rot_zyx(rx, ry, rz):
    """R = Rz(rz) Ry(ry) Rx(rx) (URDF's roll-pitch-yaw, kincal's frame blocks)."""
    cx, sx, cy, sy, cz, sz = (math.cos(rx), math.sin(rx), math.cos(ry), math.sin(ry),
                              math.cos(rz), math.sin(rz))
    return np.array([[cz * cy, cz * sy * sx - sz * cx, cz * sy * cx + sz * sx],
                     [sz * cy, sz * sy * sx + cz * cx, sz * sy * cx - cz * sx],
                     [-sy, cy * sx, cy * cx]])


def zyx_rates(rx, ry, rz):
    """Columns: the angular velocity (in the block's parent frame) of a unit rate of rx, ry, rz."""
    cy, sy, cz, sz = math.cos(ry), math.sin(ry), math.cos(rz), math.sin(rz)
    return np.array([[cz * cy, -sz, 0.0], [sz * cy, cz, 0.0], [-sy, 0.0, 1.0]])


def frame_block(v):
    """(R, t) of a frame block's six values x, y, z, rx, ry, rz."""
    return rot_zyx(v[3], v[4], v[5]), np.asarray(v[:3], dtype=float)


def exp_so3(w):
    """Rotation matrices of rotation vectors w, shape (N, 3) -> (N, 3, 3)."""
    theta = np.linalg.norm(w, axis=1)
    small = theta < 1e-8
    th = np.where(small, 1.0, theta)
    a = np.where(small, 1.0 - theta ** 2 / 6.0, np.sin(th) / th)
    b = np.where(small, 0.5 - theta ** 2 / 24.0, (1.0 - np.cos(th)) / th ** 2)
    K = hat(w)
    return np.eye(3) + a[:, None, None] * K + b[:, None, None] * (K @ K)


def hat(w):
    K = np.zeros(w.shape[:-1] + (3, 3))
    K[..., 0, 1], K[..., 0, 2], K[..., 1, 2] = -w[..., 2], w[..., 1], -w[..., 0]
    K[..., 1, 0], K[..., 2, 0], K[..., 2, 1] = w[..., 2], -w[..., 1], w[..., 0]
    return K


def log_so3(R):
    """Rotation vectors of rotation matrices near the identity (angles well below pi)."""
    c = np.clip((np.trace(R, axis1=1, axis2=2) - 1.0) / 2.0, -1.0, 1.0)
    theta = np.arccos(c)
    v = np.stack([R[:, 2, 1] - R[:, 1, 2], R[:, 0, 2] - R[:, 2, 0], R[:, 1, 0] - R[:, 0, 1]], 1)
    small = theta < 1e-6
    f = np.where(small, 0.5 + theta ** 2 / 12.0, theta / (2.0 * np.sin(np.where(small, 1.0, theta))))
    return f[:, None] * v


def left_jacobian_inverse(phi):
    """J_l^-1(phi) of SO(3), (N, 3) -> (N, 3, 3): d log(exp(d) exp(phi)) / dd at d = 0."""
    theta = np.linalg.norm(phi, axis=1)
    small = theta < 1e-4
    th = np.where(small, 1.0, theta)
    k = np.where(small, 1.0 / 12.0 + theta ** 2 / 720.0,
                 1.0 / th ** 2 - (1.0 + np.cos(th)) / (2.0 * th * np.sin(th)))
    P = hat(phi)
    return np.eye(3) - 0.5 * P + k[:, None, None] * (P @ P)


class UrdfArm:
    """The chain of a URDF from its root link to `tip`, lengths in mm."""

    def __init__(self, path, tip):
        robot = ET.parse(path).getroot()
        by_child, children = {}, set()
        for j in robot.findall("joint"):
            o = j.find("origin")
            xyz = [float(v) * 1000.0 for v in (o.get("xyz", "0 0 0") if o is not None
                                               else "0 0 0").split()]
            rpy = [float(v) for v in (o.get("rpy", "0 0 0") if o is not None
                                      else "0 0 0").split()]
            a = j.find("axis")
            axis = np.array([float(v) for v in (a.get("xyz") if a is not None
                                                else "1 0 0").split()])
            child = j.find("child").get("link")
            by_child[child] = (j.get("name"), j.get("type"), rot_zyx(*rpy), np.array(xyz),
                               axis / np.linalg.norm(axis), j.find("parent").get("link"))
            children.add(child)
        path_joints, link = [], tip
        while link in by_child:
            path_joints.append(by_child[link])
            link = by_child[link][5]
        self.root = link
        # Moving joints with the fixed joints before each folded into its constant origin C.
        self.joints = []  # (name, kind, C_R, C_t, axis)
        R, t = np.eye(3), np.zeros(3)
        for name, kind, oR, ot, axis, _ in reversed(path_joints):
            R, t = R @ oR, t + R @ ot
            if kind == "fixed":
                continue
            if kind not in ("revolute", "continuous", "prismatic"):
                raise SystemExit("%s: joint %s of type %s is not supported" % (path, name, kind))
            self.joints.append((name, "prismatic" if kind == "prismatic" else "revolute", R, t,
                                axis))
            R, t = np.eye(3), np.zeros(3)
        self.tip = (R, t)
        self.names = [j[0] for j in self.joints]

    def parameter_names(self):
        """The mechanism's parameters, in the order kincal lists them, with their class in
        the identifiable-set choice (1 frames no link hangs from, 2 offsets, 3 origins)."""
        names = [("base." + c, 1) for c in FRAME]
        for j in self.names:
            names += [("%s.origin.%s" % (j, c), 3) for c in FRAME] + [(j + ".offset", 2)]
        names += [("tool." + c, 1) for c in FRAME]
        return names

    def walk(self, p, q, motions=True):
        """End frames (R (N,3,3), t (N,3)) for the parameter vector p (mechanism part, in
        parameter_names' order) and joint values q (N, joints); with motions, also one
        (kind, u, o) per parameter: kind 't' a translation along u, 'r' a turn about u
        through o (u, o: (3,) or (N, 3) arrays in base coordinates)."""
        n = q.shape[0]
        moves = []
        BR, Bt = frame_block(p[0:6])
        if motions:
            E = zyx_rates(*p[3:6])
            moves += [("t", np.eye(3)[k], None) for k in range(3)]
            moves += [("r", E[:, k], Bt) for k in range(3)]
        R = np.broadcast_to(BR, (n, 3, 3))
        t = np.broadcast_to(Bt, (n, 3))
        for i, (name, kind, CR, Ct, axis) in enumerate(self.joints):
            e = p[6 + 7 * i: 13 + 7 * i]
            ER, Et = frame_block(e[:6])
            t = t + R @ Ct
            R = R @ CR
            if motions:
                W = R @ zyx_rates(*e[3:6])
                o = t + R @ Et
                moves += [("t", R[:, :, k], None) for k in range(3)]
                moves += [("r", W[:, :, k], o) for k in range(3)]
            t = t + R @ Et
            R = R @ ER
            v = q[:, i] + e[6]
            if kind == "revolute":
                if motions:
                    moves.append(("r", R @ axis, t))
                K = hat(axis)
                M = (np.eye(3) + np.sin(v)[:, None, None] * K
                     + (1.0 - np.cos(v))[:, None, None] * (K @ K))
                R = R @ M
            else:
                u = R @ axis
                if motions:
                    moves.append(("t", u, None))
                t = t + u * v[:, None]
        t = t + R @ self.tip[1]
        R = R @ self.tip[0]
        tool = p[6 + 7 * len(self.joints):]
        TR, Tt = frame_block(tool)
        if motions:
            W = R @ zyx_rates(*tool[3:6])
            moves += [("t", R[:, :, k], None) for k in range(3)]
            moves += [("r", W[:, :, k], t + R @ Tt) for k in range(3)]
        t = t + R @ Tt
        R = R @ TR
        return R, t, moves


def point_motion(kind, u, o, x):
    """How the point x (N, 3) moves under a motion: d x per unit of the parameter."""
    if kind == "t":
        return np.broadcast_to(u, x.shape)
    return np.cross(u, x - o)
