"""python3 -m gmslab.sweep is the sweep command; python3 -m gmslab prints the version of the core."""
import gmslab

print("gmslab Python module; functions:", ", ".join(gmslab.__all__))
