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

# crank -> RPR with an offset slot, a point on the lever -> RRP on an inclined guide, branch -1
OFFSET_CHAIN = """
title = "offset slot and inclined guide"
[frame]
O = [0.0, 0.0]
B = [0.05, -0.3]
[crank]
pivot = "O"
joint = "A"
length = 0.1
positions = 13
omega = -6.0
epsilon = 3.0
[[group]]
type = "RPR"
links = [2, 3]
joints = ["A", "B"]
offset = 0.03
[[point]]
name = "C"
link = 3
from = "B"
along = 0.6
across = -0.02
[[group]]
type = "RRP"
links = [4, 5]
joints = ["C", "D"]
length = 0.35
guide = { through = [0.0, 0.35], angle_deg = 10.0 }
branch = -1
[[point]]
name = "S4"
link = 4
from = "C"
along = 0.1
across = 0.03
"""
# two RRR dyads in a chain; the second hangs on a point of the first's rocker (J2 frame,
# J1 moving) and a third point rides on the second coupler
SIX_BAR = """
title = "Watt-type six-bar"
[frame]
O = [0.0, 0.0]
O1 = [0.3, -0.1]
O2 = [0.6, 0.25]
[crank]
pivot = "O"
joint = "A"
length = 0.08
positions = 13
omega = 12.0
epsilon = -4.0
[[group]]
type = "RRR"
links = [2, 3]
joints = ["A", "B", "O1"]
lengths = [0.35, 0.2]
branch = 1
[[point]]
name = "C"
link = 3
from = "O1"
along = 0.3
across = 0.05
[[group]]
type = "RRR"
links = [4, 5]
joints = ["C", "D", "O2"]
lengths = [0.3, 0.25]
branch = -1
[[point]]
name = "S4"
link = 4
from = "D"
along = -0.1
across = 0.04
"""

# a four-bar collinear at phi = 0: a change point (tests of toggles and numbers out)
CHANGE_POINT = """
title = "four-bar at a change point (collinear at phi = 0)"
[frame]
O = [0.0, 0.0]
O1 = [1.0, 0.0]
[crank]
pivot = "O"
joint = "A"
length = 0.5
omega = 10.0
[[group]]
type = "RRR"
links = [2, 3]
joints = ["A", "B", "O1"]
lengths = [1.0, 0.5]
branch = 1
[[point]]
name = "S2"
link = 2
from = "A"
along = 0.5
[[mass]]
link = 2
mass = 2.0
inertia = 0.1
centre = "S2"
[[force]]
link = 3
moment = 5.0
"""
