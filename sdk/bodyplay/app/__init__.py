"""The game kit: what every example game shares (see docs/game-kit.md).

A game subclasses :class:`Game` (setup, fixed-step update, draw a :class:`Scene`,
summary); :func:`run_game` plays it from any input (webcam, capture, recording,
clip, the game's virtual player) in a pygame window or headless to an mp4 plus
summary.json; :func:`game_main` is the one command line of every game.
"""

from bodyplay.app.analysis import HandKinematics, HandTrace, Marker, plot_hand_motion
from bodyplay.app.cli import game_argument_parser, game_main, preferred_tracker
from bodyplay.app.game import STAGES, Game, GameContext
from bodyplay.app.hud import camera_inset
from bodyplay.app.inputs import GameInput, open_game_input
from bodyplay.app.options import VIRTUAL_INPUT, GameOptions, display_available, make_game_options
from bodyplay.app.renderer import SceneRenderer
from bodyplay.app.runner import GameError, GameResult, run_game
from bodyplay.app.scene import AVATAR_COLOR, LOST_COLOR, Scene

__all__ = [
    "AVATAR_COLOR",
    "LOST_COLOR",
    "STAGES",
    "VIRTUAL_INPUT",
    "Game",
    "GameContext",
    "GameError",
    "GameInput",
    "GameOptions",
    "GameResult",
    "HandKinematics",
    "HandTrace",
    "Marker",
    "Scene",
    "SceneRenderer",
    "camera_inset",
    "display_available",
    "game_argument_parser",
    "game_main",
    "make_game_options",
    "open_game_input",
    "plot_hand_motion",
    "preferred_tracker",
    "run_game",
]
