"""Studies run on the batch tools or through roslaunch: robust (scenario family), noise,
config_mutation (broken YAML keys through roslaunch; the mutations themselves in
yaml_mutations), l1_reference_margin (the time-delay margin of l1's loops, computed, no tool
run). scripts/<name>_study are their entry points.
"""


def family_noise_seed(seed, scenario):
    """The noise seed preadapt_family gives scenario `scenario` of the family `seed` (its
    src/tools/family_draw.cpp), so that a study re-running one scenario draws the same
    noise."""
    return seed * 1000003 + scenario
