"""Studies run on the batch tools or through roslaunch: robust (scenario family), noise,
config_mutation (broken YAML keys through roslaunch; the mutations themselves in
yaml_mutations). scripts/<name>_study are their entry points.
"""
