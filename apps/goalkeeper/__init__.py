"""Goalkeeper: balls fly at the player, who blocks them with hands, arms, body and head.

``python -m apps.goalkeeper --headless --out out/goalkeeper`` plays a round against
the embedded virtual keeper (a reaching controller filmed by the synthetic camera
and tracked by the color-shirt tracker). See docs/goalkeeper.md.
"""
