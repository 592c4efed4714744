"""RockingBlock/RockingBlockED.cpp: a block dropped flat from rest onto its two corners, e = 0.9,
EventDriven + LsodarOSI with time events every 0.005, to T = 2."""

EXAMPLE = "examples/mechanics/RockingBlock/RockingBlockED.cpp"
SCHEME = {"kind": "ED", "h": 0.005}
SCHEME_TEXT = ("EventDriven + LsodarOSI, LCPs at impact and acceleration level, "
               "TimeDiscretisation 0.005; the corners as LagrangianScleronomousR from C plugins "
               "(plugins/rocking_block_ed.c)")


def spec(model):
    p = model["params"]
    names = [c["name"] for c in model["constraints"]]
    if names != ["corner1", "corner2"]:
        raise ValueError(f"{model['name']}: constraints {names}, not corner1, corner2")
    e = {c["name"]: c["e"] for c in model["constraints"]}
    return {
        "t_end": model["t_end"],
        "ds": [{"kind": "linear", "coords": ["x", "y", "theta"], "q0": model["q0"],
                "v0": model["v0"],
                "mass": [[p["m"], 0.0, 0.0], [0.0, p["m"], 0.0], [0.0, 0.0, p["I"]]],
                "fext": [0.0, -p["m"] * p["g"], 0.0]}],
        "interactions": [
            {"name": f"corner{k}", "e": e[f"corner{k}"], "ds": [0],
             "relation": {"kind": "scleronomous", "plugin": "block", "h": f"h{k}",
                          "G0": f"G{k}", "dotG0": f"G{k}dot"}} for k in (1, 2)],
        "plugins": {"block": {"source": "rocking_block_ed.c",
                              "defines": {"LEN": p["L"], "HEIGHT": p["H"]}}},
    }


DISCUSSION = """The block is dropped flat, so both corners land together at every impact and it bounces
without rocking: four impacts before t_end, each on both corners. zenosim agrees with the
closed form to 2e-15 at every tolerance, Siconos to about 2.5 tol (plugins for the corners,
as the example has). Both are right; zenosim is about a hundred times faster (0.019 ms against
2.1 ms)."""
