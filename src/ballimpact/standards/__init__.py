"""Published ball test methods (docs/standards.md): the quantities a lab certifies balls by, from
a folder of its records or from a ball model.

Three methods, each described by its facts only (speeds, quantities, formulas):

- `cor` (ASTM F1887): the ball is fired at 60 mph (26.8224 m/s) at a massive, rigid, flat wall;
  COR = rebound speed / inbound speed, both measured near the wall.
- `dynamic-stiffness` (ASTM F2845's quantity): DS = (1/m) (F_peak / v_in)^2 from the load-cell
  peak force (N/m; also in lbf/in, 1 lbf/in = 175.1268 N/m), `features.extract_features`'
  `dynamic_stiffness_n_m` used as it is. F2845 itself fires the ball at a rigid cylindrical
  surface at a speed of its own; here the nominal speed is 60 mph against a flat rigid plane (a
  choice: the one the other impact method uses; `nominal=` / `--impact-speed-m-s` sets it).
- `compression` (ASTM F1888): the ball squeezed between two flat rigid platens by 0.25 in
  (6.35 mm), slowly; the force at that displacement (N, and lbf as the method quotes it).

Two paths per method:

- `from_records(method, paths, ...)`: a lab's records (impact records as `ballimpact features`
  reads them, with their JSON side files; compression curves as `calibrate --compression` reads
  them), one value of the method's quantities per shot, grouped by ball (the ball id comes from
  the file name, `ball_id`) into mean, standard deviation and count per ball, and over the balls
  into the mean and standard deviation of the ball means (each ball counts once, whatever its
  number of shots). Standard deviations are sample ones (n - 1 in the denominator); one value has
  none (NaN, null in JSON).
- `on_model(method, ball, ...)`: the method run on a ball model (`fe.simulate` at the method's
  speed on a rigid plane, or `fe.compress` to its displacement), with the model's cost.

An impact record whose inbound speed is more than `SPEED_TOLERANCE_M_S` from the method's speed
gets a warning naming its file (the record is still used: the methods allow other speeds if the
report says so, and the warning does).

The modules: `methods` (the facts, ball ids, the speed checks), `lab` (`from_records`), `model`
(`on_model`), `results` (statistics, text, the CSV table).

Kept apart from `METHODS` (it needs a bat, not a rigid wall, and runs on the bat's model only):
`bbcor` (ASTM F2219 / NCAA BBCOR), the bat-ball COR of a baseball bat; docs/equipment.md,
"BBCOR".
"""

from .methods import (
    ALIASES as ALIASES,
    COMPRESSION_STEPS as COMPRESSION_STEPS,
    DEFAULT_BALL_PATTERN as DEFAULT_BALL_PATTERN,
    INCH_M as INCH_M,
    METHODS as METHODS,
    Method as Method,
    QUARTER_INCH_M as QUARTER_INCH_M,
    Quantity as Quantity,
    SIXTY_MPH_M_S as SIXTY_MPH_M_S,
    SPEED_TOLERANCE_M_S as SPEED_TOLERANCE_M_S,
    ball_id_function as ball_id_function,
    checked_speed as checked_speed,
    describe_methods as describe_methods,
    get_method as get_method,
    speed_note as speed_note,
)
from .lab import (
    compression_quantities as compression_quantities,
    from_records as from_records,
    impact_quantities as impact_quantities,
)
from .model import (
    on_model as on_model,
)
from .bbcor import (
    BBCOR_METHOD as BBCOR_METHOD,
    BBCORMethod as BBCORMethod,
    BBCORResult as BBCORResult,
    bbcor as bbcor,
    bbcor_certification as bbcor_certification,
    bbcor_of as bbcor_of,
)
from .run import (
    run_method as run_method,
)
from .specification import (
    write_specified_ball as write_specified_ball,
)
from .results import (
    shot_stats as shot_stats,
    stats_text as stats_text,
    summarise as summarise,
    table_rows as table_rows,
    write_result_table as write_result_table,
)

__all__ = ["ALIASES", "BBCOR_METHOD", "BBCORMethod", "BBCORResult", "COMPRESSION_STEPS",
           "DEFAULT_BALL_PATTERN", "INCH_M", "METHODS", "Method", "QUARTER_INCH_M", "Quantity",
           "SIXTY_MPH_M_S", "SPEED_TOLERANCE_M_S", "ball_id_function", "bbcor",
           "bbcor_certification", "bbcor_of", "checked_speed", "compression_quantities",
           "describe_methods", "from_records", "get_method", "impact_quantities", "on_model",
           "run_method", "shot_stats", "speed_note", "stats_text", "summarise", "table_rows",
           "write_result_table", "write_specified_ball"]
