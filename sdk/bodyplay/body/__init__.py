"""The body: joint set, skeleton and forward kinematics, body sizes, meshes, the shirt."""

from bodyplay.body.actor import Actor, load_actor
from bodyplay.body.joints import BONES, JOINT_INDEX, JOINT_NAMES, NUM_JOINTS, UPPER_BODY
from bodyplay.body.mesh import body_mesh
from bodyplay.body.shapes import BODY_SHAPES, BodyShape, body_shape, closest_body_shape
from bodyplay.body.skeleton import NODE_NAMES, NODE_PARENTS, Skeleton
from bodyplay.body.skinning import MATERIAL_RGB, Material, SkinnedMesh

__all__ = [
    "BODY_SHAPES",
    "BONES",
    "BodyShape",
    "JOINT_INDEX",
    "JOINT_NAMES",
    "NODE_NAMES",
    "NODE_PARENTS",
    "NUM_JOINTS",
    "Skeleton",
    "UPPER_BODY",
    "body_shape",
    "closest_body_shape",
    "MATERIAL_RGB",
    "Material",
    "SkinnedMesh",
    "body_mesh",
    "Actor",
    "load_actor",
]
