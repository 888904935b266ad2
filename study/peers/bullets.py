"""What each runner does with ``sim.Body(bullet=True)``, recorded in its ``settings``.

A bullet is a fast body that must not pass through moving bodies either (sim sweeps it against
every body, Box2D too). Chipmunk has no continuous collision at all, and the pybullet runner
enables none, so there a bullet is an ordinary body and may pass through a thin one (a 100 m/s
box through a 5 cm plank). Refusing such a scene would take the peers out of any experiment that
fires one; running it silently would hide sim's advantage. Each runner records instead how many
bodies asked and whether it honoured them, so the results say which rows ran without it.
"""


def bullets(scene, honoured, how):
    """The ``settings["bullets"]`` entry: {"asked": bodies with bullet=True, "of": bodies,
    "honoured": whether the engine sweeps them against moving bodies, "how": what it does}."""
    asked = sum(1 for b in scene.bodies if b.bullet)
    return {"asked": asked, "of": len(scene.bodies), "honoured": bool(honoured), "how": how}
