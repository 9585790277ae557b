"""One symbolic module per mechanism; ``MECHANISMS`` maps each registered name to the function that
derives its ``codegen.ModuleSpec`` (a module may derive several variants)."""

from functools import partial

from symbolic.mechanisms import five_bar, passive_leg, slider_gantry, ups_pu

MECHANISMS = {
    "five_bar": five_bar.module,
    "passive_leg": passive_leg.module,
    "slider_gantry": partial(slider_gantry.module, symmetric=False),
    "slider_gantry_symmetric": partial(slider_gantry.module, symmetric=True),
    "ups_pu": ups_pu.module,
}
