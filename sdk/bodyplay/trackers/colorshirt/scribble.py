"""A small pygame window for the paper's scribble initialization of the white balance.

Shows one camera frame; keys ``0``-``9`` pick a shirt color (the legend along the
bottom shows which), dragging the mouse scribbles that color's label onto the
patch under the cursor, Backspace clears, Enter (or closing the window) finishes.
The scribbles give ``W`` through
:func:`bodyplay.trackers.colorshirt.whitebalance.white_balance_from_scribbles`.
Runs windowed only; tests import it but never open it.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from bodyplay.body.shirt import SHIRT_COLORS
from bodyplay.errors import ConfigError
from bodyplay.trackers.colorshirt.colors import ColorModel, default_color_model
from bodyplay.trackers.colorshirt.whitebalance import white_balance_from_scribbles

__all__ = ["collect_scribbles", "scribble_white_balance"]

_BRUSH = 4
_LEGEND_H = 28


def collect_scribbles(image: NDArray[np.uint8], title: str = "bodyplay: scribble on the shirt"
                      ) -> NDArray[np.int64]:
    """Open a window over the RGB ``image``; return (H, W) color indices, -1 unscribbled."""
    import pygame

    h, w = image.shape[:2]
    labels = np.full((h, w), -1, np.int64)
    pygame.init()
    try:
        screen = pygame.display.set_mode((w, h + _LEGEND_H))
        pygame.display.set_caption(title)
        photo = pygame.surfarray.make_surface(np.ascontiguousarray(image.swapaxes(0, 1)))
        font = pygame.font.Font(None, 20)
        current = 0
        drawing = False
        clock = pygame.time.Clock()
        running = True
        while running:
            for ev in pygame.event.get():
                if ev.type == pygame.QUIT:
                    running = False
                elif ev.type == pygame.KEYDOWN:
                    if ev.key in (pygame.K_RETURN, pygame.K_KP_ENTER):
                        running = False
                    elif ev.key == pygame.K_BACKSPACE:
                        labels[:] = -1
                    elif pygame.K_0 <= ev.key <= pygame.K_9:
                        current = ev.key - pygame.K_0
                elif ev.type == pygame.MOUSEBUTTONDOWN:
                    drawing = True
                elif ev.type == pygame.MOUSEBUTTONUP:
                    drawing = False
            if drawing:
                x, y = pygame.mouse.get_pos()
                if y < h:
                    ys_ = slice(max(0, y - _BRUSH), y + _BRUSH)
                    labels[ys_, max(0, x - _BRUSH) : x + _BRUSH] = current
            screen.blit(photo, (0, 0))
            ys, xs = np.nonzero(labels >= 0)
            for y, x in zip(ys[::7], xs[::7], strict=True):
                screen.set_at((int(x), int(y)), SHIRT_COLORS[int(labels[y, x])].rgb)
            cell = w / len(SHIRT_COLORS)
            for k, c in enumerate(SHIRT_COLORS):
                rect = pygame.Rect(int(k * cell), h, int(cell), _LEGEND_H)
                pygame.draw.rect(screen, c.rgb, rect)
                if k == current:
                    pygame.draw.rect(screen, (0, 0, 0), rect, 3)
                screen.blit(font.render(str(k), True, (0, 0, 0)), (rect.x + 4, h + 6))
            pygame.display.flip()
            clock.tick(30)
    finally:
        pygame.quit()
    return labels


def scribble_white_balance(image: NDArray[np.uint8], model: ColorModel | None = None
                           ) -> NDArray[np.float64]:
    """Let the user scribble on ``image`` and return the white balance ``W``."""
    labels = collect_scribbles(image)
    if not np.any(labels >= 0):
        raise ConfigError("no scribbles were drawn; scribble on at least three patches")
    return white_balance_from_scribbles(image, labels, model or default_color_model())
