"""The goalkeeper's rules, scene and summary; never imports a window."""

from apps.goalkeeper.game.goalkeeper import GoalkeeperGame
from apps.goalkeeper.game.rules import PART_GROUPS, GoalkeeperOptions, part_group
from apps.goalkeeper.game.shots import Goal, Shot, plan_round

__all__ = ["PART_GROUPS", "Goal", "GoalkeeperGame", "GoalkeeperOptions", "Shot", "part_group",
           "plan_round"]
