"""The single-camera silhouette tracker (papers/single-camera-silhouette-mocap.txt).

Background subtraction, distance-transform template matching against a hierarchy of
pose silhouettes and a tree-based Bayesian filter (see DESIGN.md). The package is
reserved for it and holds no code yet.
"""
