"""Scene texts shared by the tests."""

# The spec's crank-rocker four-bar (shared/spec/scene.md), headers tagged with unique comments.
FOURBAR = """\
title  = "Crank-rocker four-bar"
author = "Student, group"

[frame]                 # fixed points
O  = [0.0, 0.0]
O1 = [0.0, -0.53]

[crank]                 # link 1
pivot    = "O"
joint    = "A"
length   = 0.14
phi0_deg = 0.0
step_deg = 30.0
positions = 13
omega    = 20.0
epsilon  = 0.0

[[group]]               # g1
type    = "RRR"
links   = [2, 3]
joints  = ["A", "B", "O1"]
lengths = [0.5, 0.34]
branch  = -1

[[point]]               # pS2
name   = "S2"
link   = 2
from   = "A"
along  = 0.39035
across = 0.0

[[point]]               # pS3
name  = "S3"
link  = 3
from  = "O1"
along = 0.2129
"""


# A four-bar whose coupler is too short for part of the revolution (it cannot assemble for
# crank angles of about 104.5-255.5 deg): the pictures and charts must leave a gap there.
SHORT = """\
title = "RRR that cannot assemble over part of the revolution"
[frame]
O = [0.0, 0.0]
O1 = [0.3, 0.0]
[crank]
pivot = "O"
joint = "A"
length = 0.2
phi0_deg = 0.0
step_deg = 30.0
positions = 13
omega = 10.0
epsilon = 0.0
[[group]]
type = "RRR"
links = [2, 3]
joints = ["A", "B", "O1"]
lengths = [0.25, 0.15]
branch = 1
"""
