"""Scenes: what is drawn and what is asked (:mod:`.scene`, loaded from TOML and checked by
:mod:`.parse`; the shipped scenes are the ``*.toml`` files of this folder), and the planner
that computes only that (:mod:`.plan`)."""

from .plan import Plan, SceneResult, execute, make_plan
from .scene import (
    CONVENTIONS,
    FIGURES,
    PAPER_SCENES,
    SCENES,
    STORY_SCENES,
    Draw,
    EllipsoidStyle,
    Scene,
    SceneError,
    load_scene,
)

__all__ = [
    "CONVENTIONS",
    "FIGURES",
    "PAPER_SCENES",
    "SCENES",
    "STORY_SCENES",
    "Draw",
    "EllipsoidStyle",
    "Scene",
    "SceneError",
    "load_scene",
    "Plan",
    "SceneResult",
    "execute",
    "make_plan",
]
