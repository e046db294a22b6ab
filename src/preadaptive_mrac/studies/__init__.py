"""Studies run on the batch tools or through roslaunch: robust (scenario family), noise,
config_mutation (broken YAML keys). One module each; scripts/<name>_study are their entry points.
"""
