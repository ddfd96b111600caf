"""A labeling-function file for TwoTileRoom-v0: ``minigrid_room_labels.py:label`` reads ``info``."""


def label(observation, info):
    tile = info.get("tile")
    return [tile] if tile else []


label.propositions = ["a", "b"]
