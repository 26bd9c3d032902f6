"""A ball the universal model was not trained on: the 3-layer cricket ball (thesis chapter 5)
simulated at 25 m/s, identified as a homogeneous universal ball with the built-in model, and the
universal ball's FE pulse compared with the layered ball's (the thesis' figures 6-11 and 6-12
question). Prints JSON; writes identify-layered.png.

    python examples/identify_layered_ball.py
"""

import json
import sys

from ballimpact.fe import load_ball, simulate
from ballimpact.records.features import extract_features
from ballimpact.universal import identify, load_model
from ballimpact.universal.plots import plot_layered


class Processed:  # what `identify` reads of a processed test: its features
    def __init__(self, features):
        self.features = features


def main(name: str = "cricket-3layer", speed: float = 25.0) -> None:
    model = load_model()
    options = model.solver_options()
    layered = simulate(load_ball(name, impact_speed_m_s=speed), speed, options)
    found = identify(Processed(extract_features(layered.record())), model, options=options)
    plot_layered(name, layered, found.simulated, found.verification, "identify-layered.png")
    print(json.dumps({"ball": name, "impact_speed_m_s": speed, "params": found.params,
                      "params_interval_90": found.interval_90,
                      "verification": found.verification, "plot": "identify-layered.png"},
                     indent=2))


if __name__ == "__main__":
    main(*sys.argv[1:2])
