"""A rendered block world for reward-machine inference from images (thesis chapter 7, Table 7.1).

Numpy only: :mod:`.world` (kinematic pick-and-place), :mod:`.render` (front and top-down
cameras with noise and lighting jitter), :mod:`.tasks` (Stack-2, Place-2, Pyramid-3, Stack-3,
Place-3 and their ground truth), :mod:`.demonstrator` (scripted demonstrations),
:mod:`.env` (the gymnasium environment a pick-and-place policy acts in).
"""
