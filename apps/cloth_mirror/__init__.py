"""The cloth mirror: the avatar takes the player's pose and its clothes move with it."""
