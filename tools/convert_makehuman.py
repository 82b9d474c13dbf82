"""One-off converter: the MakeHuman hm08 base mesh -> sdk/bodyplay/assets/actor.npz.

Reads ../shared/data/mesh/makehuman (CC0): base.obj (decimetres, Y up, A-pose),
basemesh_vertex_groups.json (body vertices; joint cubes and helper geometry are
dropped), rig.cmu_mb.json (CMU-named bones whose heads/tails are joint-cube
centroids), weights.cmu_mb.json (per-bone skin weights).

The A-pose is re-posed into bodyplay's rest T-pose by linear blend skinning with the
MakeHuman weights: each arm segment (upper arm, forearm, hand) is rotated about its
head joint onto +-X, each leg segment onto -Y, feet are kept flat on the floor (this
replaces the t-pose.cmu_mb.json Euler angles, which are relative to Blender bone
rolls). Joint centres are then measured on the re-posed cubes (shoulders, elbows,
wrists, hips, knees, ankles) and on the mesh (head centre midway between the ears),
giving the actor's own skeleton rest offsets. CMU bone weights are mapped to
skeleton nodes (top 4, renormalized) and the body is dressed with the shirt rules of
:mod:`bodyplay.body.dress`.

Run from the repository root: ``.venv/bin/python tools/convert_makehuman.py``.
"""

from __future__ import annotations

import argparse
import json
from pathlib import Path

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.dress import dress_points, torso_profile
from bodyplay.body.rotations import rotation_between
from bodyplay.body.skeleton import NODE_NAMES, NODE_PARENTS

ROOT = Path(__file__).resolve().parents[1]
SRC = ROOT.parent / "shared" / "data" / "mesh" / "makehuman"
OUT = ROOT / "sdk" / "bodyplay" / "assets" / "actor.npz"

BONE_TO_NODE = {
    "Hips": "pelvis", "LHipJoint": "pelvis", "RHipJoint": "pelvis",
    "LowerBack": "lumbar", "Spine": "lumbar", "Spine1": "thorax",
    "Neck": "neck", "Neck1": "neck", "Head": "head",
    "LeftShoulder": "l_clavicle", "LeftArm": "l_shoulder", "LeftForeArm": "l_elbow",
    "LeftHand": "l_wrist", "LeftFingerBase": "l_wrist", "LeftHandFinger1": "l_wrist",
    "LThumb": "l_wrist",
    "RightShoulder": "r_clavicle", "RightArm": "r_shoulder", "RightForeArm": "r_elbow",
    "RightHand": "r_wrist", "RightFingerBase": "r_wrist", "RightHandFinger1": "r_wrist",
    "RThumb": "r_wrist",
    "LeftUpLeg": "l_hip", "LeftLeg": "l_knee", "LeftFoot": "l_ankle", "LeftToeBase": "l_ankle",
    "RightUpLeg": "r_hip", "RightLeg": "r_knee", "RightFoot": "r_ankle",
    "RightToeBase": "r_ankle",
}

# bones re-aimed onto a world direction (T-pose), and bones kept at world orientation
AIM = {
    "LeftArm": (1, 0, 0), "LeftForeArm": (1, 0, 0), "LeftHand": (1, 0, 0),
    "RightArm": (-1, 0, 0), "RightForeArm": (-1, 0, 0), "RightHand": (-1, 0, 0),
    "LeftUpLeg": (0, -1, 0), "LeftLeg": (0, -1, 0),
    "RightUpLeg": (0, -1, 0), "RightLeg": (0, -1, 0),
}
KEEP_WORLD = ("LeftFoot", "RightFoot")

NOTICE = (
    "actor.npz is derived from the MakeHuman hm08 base mesh, its cmu_mb rig and skin "
    "weights (https://www.makehumancommunity.org), released under CC0 1.0 Universal by "
    "Data Collection AB, Joel Palmius and Jonas Hauquier (2020). Converted by "
    "tools/convert_makehuman.py: body vertices only, re-posed to a T-pose, metres."
)


def read_obj(path: Path) -> tuple[NDArray[np.float64], list[list[int]]]:
    """All vertices (metres) and the faces (0-based, polygons) of group ``body``."""
    verts: list[list[float]] = []
    faces: list[list[int]] = []
    group = ""
    with path.open() as fh:
        for line in fh:
            if line.startswith("v "):
                verts.append([float(t) for t in line.split()[1:4]])
            elif line.startswith("g "):
                group = line.split()[1]
            elif line.startswith("f ") and group == "body":
                faces.append([int(t.split("/")[0]) - 1 for t in line.split()[1:]])
    return np.asarray(verts) * 0.1, faces


def group_indices(groups: dict[str, list[list[int]]], name: str) -> NDArray[np.int64]:
    """Vertex indices of a vertex group given as inclusive ranges."""
    return np.concatenate([np.arange(a, b + 1) for a, b in groups[name]])


def main(argv: list[str] | None = None) -> int:
    """Convert and write the asset; prints a summary."""
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--src", type=Path, default=SRC)
    ap.add_argument("--out", type=Path, default=OUT)
    args = ap.parse_args(argv)

    V_all, polys = read_obj(args.src / "base.obj")
    groups = json.loads((args.src / "basemesh_vertex_groups.json").read_text())
    rig = json.loads((args.src / "rig.cmu_mb.json").read_text())
    weights = json.loads((args.src / "weights.cmu_mb.json").read_text())["weights"]
    body = group_indices(groups, "body")
    assert body.min() == 0 and body.max() == len(body) - 1
    nb = len(body)
    tris = np.array([[p[0], p[i], p[i + 1]] for p in polys for i in range(1, len(p) - 1)])
    assert tris.max() < nb, "body faces must only use body vertices"

    def cube(name: str) -> NDArray[np.float64]:
        return V_all[group_indices(groups, name)].mean(0)

    def end(spec: dict) -> NDArray[np.float64]:
        if spec["strategy"] == "CUBE":
            return cube(spec["cube_name"])
        return V_all[spec["vertex_indices"]].mean(0)

    heads = {b: end(s["head"]) for b, s in rig.items()}
    tails = {b: end(s["tail"]) for b, s in rig.items()}
    order: list[str] = []
    while len(order) < len(rig):
        for b, s in rig.items():
            if b not in order and (s["parent"] == "" or s["parent"] in order):
                order.append(b)

    # ---- re-pose A -> T by LBS about each bone's head --------------------------------
    G: dict[str, NDArray[np.float64]] = {}
    new_head: dict[str, NDArray[np.float64]] = {}

    def transform(b: str, x: NDArray[np.float64]) -> NDArray[np.float64]:
        return (x - heads[b]) @ G[b].T + new_head[b]

    for b in order:
        p = rig[b]["parent"]
        Gp = np.eye(3) if p == "" else G[p]
        new_head[b] = heads[b] if p == "" else transform(p, heads[b])
        if b in AIM:
            d = Gp @ (tails[b] - heads[b])
            G[b] = rotation_between(d, np.asarray(AIM[b], float)) @ Gp
        elif b in KEEP_WORLD:
            G[b] = np.eye(3)
        else:
            G[b] = Gp
    W = np.zeros((nb, len(order)))
    for j, b in enumerate(order):
        for vi, w in weights.get(b, []):
            if vi < nb:
                W[vi, j] += w
    assert np.all(W.sum(1) > 0), "every body vertex needs a skin weight"
    W /= W.sum(1, keepdims=True)
    verts = np.zeros((nb, 3))
    for j, b in enumerate(order):
        verts += W[:, j : j + 1] * transform(b, V_all[:nb])

    # ---- skeleton nodes measured on the re-posed body ---------------------------------
    N = {n: i for i, n in enumerate(NODE_NAMES)}
    J = np.zeros((len(NODE_NAMES), 3))
    for s, side in (("l", "Left"), ("r", "Right")):
        J[N[f"{s}_clavicle"]] = new_head[f"{side}Shoulder"]
        J[N[f"{s}_shoulder"]] = new_head[f"{side}Arm"]
        J[N[f"{s}_elbow"]] = new_head[f"{side}ForeArm"]
        J[N[f"{s}_wrist"]] = new_head[f"{side}Hand"]
        J[N[f"{s}_hand"]] = transform(f"{side}Hand", cube(f"joint-{s}-finger-3-1"))
        J[N[f"{s}_hip"]] = new_head[f"{side}UpLeg"]
        J[N[f"{s}_knee"]] = new_head[f"{side}Leg"]
        J[N[f"{s}_ankle"]] = new_head[f"{side}Foot"]
        J[N[f"{s}_toe"]] = new_head[f"{side}ToeBase"]
    J[N["pelvis"]] = 0.5 * (J[N["l_hip"]] + J[N["r_hip"]])
    J[N["lumbar"]] = cube("joint-spine-3")
    J[N["thorax"]] = cube("joint-spine-1")
    J[N["neck"]] = cube("joint-neck")
    node_of_bone = np.array([N[BONE_TO_NODE[b]] for b in order])
    NW = np.zeros((nb, len(NODE_NAMES)))
    for j in range(len(order)):
        NW[:, node_of_bone[j]] += W[:, j]
    # head centre: midway between the ears (the widest points of the head)
    hv = verts[(NW[:, N["head"]] > 0.9) & (verts[:, 1] > cube("joint-head")[1])]
    ears = hv[[np.argmax(hv[:, 0]), np.argmin(hv[:, 0])]]
    J[N["head"]] = np.array([0.0, ears[:, 1].mean(), ears[:, 2].mean()])
    J[N["head_top"]] = np.array([0.0, verts[:, 1].max(), J[N["head"], 2]])
    # floor at the soles, pelvis above the origin
    shift = np.array([-J[N["pelvis"], 0], -verts[:, 1].min(), -J[N["pelvis"], 2]])
    verts += shift
    J += shift
    offsets = np.array([J[i] - (J[p] if p >= 0 else 0.0) for i, p in enumerate(NODE_PARENTS)])
    offsets[0] = 0.0

    # ---- skin weights on nodes: top 4, renormalized ---------------------------------
    top = np.argsort(-NW, axis=1)[:, :4]
    tw = np.take_along_axis(NW, top, 1)
    tw /= tw.sum(1, keepdims=True)

    # ---- dress ------------------------------------------------------------------------
    dom = top[:, 0]
    prof = torso_profile(verts, dom, J)
    vmat, vpart = dress_points(verts, dom, J, prof)
    fw = NW[tris].sum(1)
    _, fpart = dress_points(verts[tris].mean(1), np.argmax(fw, 1), J, prof)

    args.out.parent.mkdir(parents=True, exist_ok=True)
    np.savez_compressed(
        args.out,
        vertices=verts.astype(np.float32),
        faces=tris.astype(np.uint16),
        bone_indices=top.astype(np.uint8),
        bone_weights=np.round(tw * 65535).astype(np.uint16),
        face_part=fpart.astype(np.uint8),
        vertex_material=vmat.astype(np.uint8),
        vertex_part=vpart.astype(np.uint8),
        rest_offsets=offsets.astype(np.float32),
        pelvis=J[N["pelvis"]].astype(np.float32),
        node_names=np.array(NODE_NAMES),
        notice=np.array(NOTICE),
    )
    print(f"wrote {args.out}: {nb} vertices, {len(tris)} triangles, "
          f"{args.out.stat().st_size / 1e6:.2f} MB; height {verts[:, 1].max():.3f} m")
    for n in ("pelvis", "l_shoulder", "l_elbow", "l_wrist", "head", "l_ankle"):
        print(f"  {n:10s} {np.round(J[N[n]], 3)}")
    print(f"  ears {np.round(ears, 3).tolist()}")
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
