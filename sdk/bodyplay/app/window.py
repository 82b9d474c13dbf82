"""The pygame window of a game run with a display: an OpenGL surface and its keys.

Keys: Esc or q quits, p or space pauses and resumes, r restarts the round.
Closing the window quits. Headless runs never import pygame's display.
"""

from __future__ import annotations

import os
from typing import Any

import moderngl

from bodyplay.render.gl import GLContextError, create_context

__all__ = ["GameWindow", "KEY_ACTIONS"]

KEY_ACTIONS: dict[str, str] = {
    "escape": "quit", "q": "quit", "p": "pause", "space": "pause", "r": "restart",
}
"""pygame key name -> runner action."""


class GameWindow:
    """A ``width`` x ``height`` pygame window with a current OpenGL 3.3 context."""

    def __init__(self, width: int, height: int, title: str) -> None:
        os.environ.setdefault("PYGAME_HIDE_SUPPORT_PROMPT", "1")
        import pygame

        self._pg: Any = pygame
        pygame.display.init()
        pygame.display.gl_set_attribute(pygame.GL_CONTEXT_MAJOR_VERSION, 3)
        pygame.display.gl_set_attribute(pygame.GL_CONTEXT_MINOR_VERSION, 3)
        pygame.display.gl_set_attribute(
            pygame.GL_CONTEXT_PROFILE_MASK, pygame.GL_CONTEXT_PROFILE_CORE
        )
        try:
            pygame.display.set_mode((width, height), pygame.OPENGL | pygame.DOUBLEBUF)
        except pygame.error as exc:
            pygame.display.quit()
            raise GLContextError(
                f"cannot open a {width}x{height} OpenGL window ({exc}); run with --headless"
            ) from exc
        pygame.display.set_caption(title)
        self.ctx: moderngl.Context = create_context(headless=False)

    def poll(self) -> list[str]:
        """The actions the player asked for since the last call (quit, pause, restart)."""
        pg = self._pg
        out: list[str] = []
        for ev in pg.event.get():
            if ev.type == pg.QUIT:
                out.append("quit")
            elif ev.type == pg.KEYDOWN:
                action = KEY_ACTIONS.get(pg.key.name(ev.key))
                if action:
                    out.append(action)
        return out

    def flip(self) -> None:
        """Show the frame drawn into the window's screen."""
        self._pg.display.flip()

    def close(self) -> None:
        """Close the window."""
        self._pg.display.quit()
