"""Scene files: every mistake gives one clear line (file:LINE, key, what was expected).

Each error case starts from a valid scene (the spec's four-bar, or a shaper-like scene
with RPR + [[point]] + RRP), introduces exactly one mistake, loads it from a real file and
checks the SceneError message: one line, "<path>:<line>: ...", the line is the one of the
offending key (or of its table's header when the key is missing), the key is named, and
the message says what was expected.
"""
from __future__ import annotations

import re
from pathlib import Path

import pytest
from helpers.scenes import FOURBAR

from sheetkin import Scene, SceneError, load_scene, parse_scene
from sheetkin.groups import kind_of

WORKBOOKS = Path(__file__).resolve().parents[2] / "workbooks"

# A shaper: group 1 (RPR) turns the slotted lever, point C sits on that lever (link 3),
# group 2 (RRP) hangs on C. C must be placed after group 1 and before group 2.
SHAPER = """\
title = "Shaper"

[frame]
B = [0.0, 0.0]
O = [0.0, 0.27]

[crank]                 # link 1
pivot     = "O"
joint     = "A"
length    = 0.1
phi0_deg  = 248.2614
step_deg  = -30.0
positions = 13
omega     = -7.854

[[group]]               # g1
type   = "RPR"
links  = [2, 3]
joints = ["A", "B"]

[[point]]               # pC
name  = "C"
link  = 3
from  = "B"
along = 0.49

[[group]]               # g2
type   = "RRP"
links  = [4, 5]
joints = ["C", "D"]
length = 0.2
guide  = { through = [0.0, 0.47], angle_deg = 0.0 }
branch = -1
"""


# --------------------------------------------------------------------------- helpers
def mutate(base: str, old: str, new: str) -> str:
    assert base.count(old) == 1, f"test bug: {old!r} must occur exactly once"
    return base.replace(old, new)


def line_of(text: str, anchor: str) -> int:
    hits = [no for no, line in enumerate(text.splitlines(), 1) if anchor in line]
    assert len(hits) == 1, f"test bug: anchor {anchor!r} found on lines {hits}"
    return hits[0]


def write(tmp_path: Path, text: str, name: str = "bad_scene.toml") -> Path:
    path = tmp_path / name
    path.write_text(text, encoding="utf-8")
    return path


def scene_error(path: Path) -> str:
    with pytest.raises(SceneError) as info:
        load_scene(path)
    return str(info.value)


def assert_one_line(msg: str):
    assert msg, "empty error message"
    assert "\n" not in msg and "\r" not in msg, f"message is not one line: {msg!r}"
    assert "Traceback" not in msg


def assert_mentions(msg: str, key: str, expects):
    assert re.search(rf"(?<![A-Za-z0-9_]){re.escape(key)}(?![A-Za-z0-9_])", msg), \
        f"key {key!r} not named in: {msg}"
    for pattern in expects:
        assert re.search(pattern, msg), f"expected /{pattern}/ in: {msg}"


def case(category, base, old, new, key, expects, anchor=None, marks=(), id=None):
    """One mistake: replace `old` by `new`; the error must point at the line holding
    `anchor` (default: the first line of `new`) and name `key` and match `expects`."""
    if anchor is None:
        anchor = new.strip().splitlines()[0]
    return pytest.param(base, old, new, key, expects, anchor, marks=marks,
                        id=f"{category}: {id or new.strip() or 'delete ' + old.strip()}")


F, S = FOURBAR, SHAPER

CASES = [
    # ---- unknown group type
    case("unknown type", F, 'type    = "RRR"', 'type    = "RRX"', "type",
         [r"'RRX'|\bRRX\b", r"\bRRR\b", r"\bRRP\b", r"\bRPR\b"]),
    case("unknown type", F, 'type    = "RRR"', 'type    = "rrr"', "type",
         [r"\brrr\b", r"\bRRR\b", r"\bRRP\b", r"\bRPR\b"]),
    case("unknown type", S, 'type   = "RRP"', 'type   = "PPP"', "type",
         [r"\bPRP\b", r"\bRRR\b", r"\bRRP\b", r"\bRPR\b"]),
    # ---- a joint or point used before it is known
    case("used before known", S, 'joints = ["A", "B"]', 'joints = ["A", "C"]', "joints",
         [r"'C'", r"later|before|not (yet )?known"],
         id="RPR uses point C on its own (not yet placed) lever"),
    case("used before known", S, 'joints = ["A", "B"]', 'joints = ["D", "B"]', "joints",
         [r"'D'", r"later|before|not (yet )?known"],
         id="group 1 uses joint D of the later group 2"),
    case("used before known", S, 'link  = 3\nfrom  = "B"', 'link  = 5\nfrom  = "D"', "joints",
         [r"'C'", r"later|before|not (yet )?known"], anchor='joints = ["C", "D"]',
         id="group 2 uses point C moved onto its own slider link 5"),
    case("used before known", S, 'joints = ["C", "D"]', 'joints = ["X", "D"]', "joints",
         [r"'X'", r"not defined|unknown"], id="group 2 uses an undefined X"),
    case("used before known", F, 'joints  = ["A", "B", "O1"]', 'joints  = ["A", "B", "S3"]',
         "joints", [r"'S3'", r"later|before|not (yet )?known"],
         id="RRR uses point S3 of its own rocker"),
    # ---- a name defined twice
    case("defined twice", F, 'name   = "S2"', 'name   = "B"', "name", [r"'B'", r"twice"]),
    case("defined twice", F, 'name  = "S3"', 'name  = "S2"', "name", [r"'S2'", r"twice"]),
    case("defined twice", F, 'name   = "S2"', 'name   = "O1"', "name", [r"'O1'", r"twice"]),
    case("defined twice", F, 'joint    = "A"', 'joint    = "O1"', "joint", [r"'O1'", r"twice"]),
    case("defined twice", F, 'joints  = ["A", "B", "O1"]', 'joints  = ["A", "O", "O1"]',
         "joints", [r"'O'", r"twice"]),
    case("defined twice", S, 'joints = ["C", "D"]', 'joints = ["C", "A"]', "joints",
         [r"'A'", r"twice"]),
    case("defined twice", F, 'O1 = [0.0, -0.53]', 'O1 = [0.0, -0.53]\nO  = [1.0, 1.0]', "O",
         [r"twice|defined|duplicate|overwrite"], anchor="O  = [1.0, 1.0]",
         id="frame point O written twice"),
    # ---- non-positive lengths
    case("non-positive length", F, "length   = 0.14", "length   = 0", "length", [r"positive"]),
    case("non-positive length", F, "length   = 0.14", "length   = -0.14", "length",
         [r"positive", r"-0\.14"]),
    case("non-positive length", F, "lengths = [0.5, 0.34]", "lengths = [0.5, 0.0]", "lengths",
         [r"positive"]),
    case("non-positive length", F, "lengths = [0.5, 0.34]", "lengths = [-0.5, 0.34]", "lengths",
         [r"positive"]),
    case("non-positive length", S, "length = 0.2", "length = -0.2", "length", [r"positive"]),
    # ---- missing keys (the line is the table's header)
    case("missing key", F, "omega    = 20.0\n", "", "omega", [r"missing", r"number"],
         anchor="# link 1"),
    case("missing key", F, 'pivot    = "O"\n', "", "pivot", [r"missing"], anchor="# link 1"),
    case("missing key", F, 'joint    = "A"\n', "", "joint", [r"missing"], anchor="# link 1"),
    case("missing key", F, "length   = 0.14\n", "", "length", [r"missing", r"number"],
         anchor="# link 1"),
    case("missing key", F, 'type    = "RRR"\n', "", "type", [r"missing"], anchor="# g1"),
    case("missing key", F, "links   = [2, 3]\n", "", "links", [r"missing", r"array|\[2, 3\]"],
         anchor="# g1"),
    case("missing key", F, 'joints  = ["A", "B", "O1"]\n', "", "joints", [r"missing", r"3"],
         anchor="# g1"),
    case("missing key", F, "lengths = [0.5, 0.34]\n", "", "lengths", [r"missing", r"2"],
         anchor="# g1"),
    case("missing key", F, "branch  = -1\n", "", "branch", [r"missing"], anchor="# g1"),
    case("missing key", S, "branch = -1\n", "", "branch", [r"missing"], anchor="# g2"),
    case("missing key", S, "length = 0.2\n", "", "length", [r"missing"], anchor="# g2"),
    case("missing key", S, "guide  = { through = [0.0, 0.47], angle_deg = 0.0 }\n", "", "guide",
         [r"missing", r"through"], anchor="# g2"),
    case("missing key", F, 'name  = "S3"\n', "", "name", [r"missing"], anchor="# pS3"),
    case("missing key", F, "link  = 3\n", "", "link", [r"missing", r"integer"], anchor="# pS3"),
    case("missing key", F, 'from  = "O1"\n', "", "from", [r"missing"], anchor="# pS3"),
    # ---- wrongly typed keys
    case("wrong type", F, "length   = 0.14", 'length   = "0.14"', "length", [r"number"]),
    case("wrong type", F, "positions = 13", "positions = 13.0", "positions", [r"integer"]),
    case("wrong type", F, "omega    = 20.0", "omega    = true", "omega", [r"number"]),
    case("wrong type", F, "epsilon  = 0.0", 'epsilon  = "0"', "epsilon", [r"number"]),
    case("wrong type", F, "phi0_deg = 0.0", "phi0_deg = [0.0]", "phi0_deg", [r"number"]),
    case("wrong type", F, 'pivot    = "O"', "pivot    = 0", "pivot", [r"string|frame point"]),
    case("wrong type", F, "branch  = -1", "branch  = -1.0", "branch", [r"integer|\+1"]),
    case("wrong type", F, "links   = [2, 3]", 'links   = [2, "3"]', "links", [r"integer"]),
    case("wrong type", F, "links   = [2, 3]", "links   = 2", "links", [r"array|\[2, 3\]"]),
    case("wrong type", F, 'joints  = ["A", "B", "O1"]', 'joints  = "A B O1"', "joints",
         [r"array"]),
    case("wrong type", F, 'joints  = ["A", "B", "O1"]', 'joints  = ["A", "B"]', "joints",
         [r"3"]),
    case("wrong type", F, "lengths = [0.5, 0.34]", "lengths = 0.5", "lengths", [r"array"]),
    case("wrong type", F, "O1 = [0.0, -0.53]", 'O1 = "0.0, -0.53"', "O1", [r"2 numbers|array"]),
    case("wrong type", F, "O1 = [0.0, -0.53]", "O1 = [0.0]", "O1", [r"2 numbers|array"]),
    case("wrong type", F, "link   = 2", 'link   = "2"', "link", [r"integer"]),
    case("wrong type", F, 'from   = "A"', "from   = 1", "from", [r"string|joint"]),
    case("wrong type", F, "along  = 0.39035", "along  = false", "along", [r"number"]),
    case("wrong type", F, 'title  = "Crank-rocker four-bar"', "title  = 42", "title",
         [r"string"]),
    case("wrong type", S, 'joints = ["A", "B"]', 'joints = ["A", "B"]\noffset = "0.1"', "offset",
         [r"number"], anchor='offset = "0.1"'),
    case("wrong type", S, "through = [0.0, 0.47]", "through = 5", "through",
         [r"frame point|\[x, y\]|2 numbers"], anchor="guide  ="),
    case("wrong type", S, "guide  = { through = [0.0, 0.47], angle_deg = 0.0 }", "guide  = 5",
         "guide", [r"table|through"]),
    case("wrong type", F, '[frame]                 # fixed points\nO  = [0.0, 0.0]\n'
         'O1 = [0.0, -0.53]', 'frame = 5', "frame", [r"table"],
         id="frame = 5 instead of a [frame] table"),
    case("wrong type", F, "[[group]]               # g1", "[group]                 # g1", "group",
         [r"\[\[group\]\]"],
         id="[group] instead of [[group]]"),
    # ---- positions < 1
    case("positions", F, "positions = 13", "positions = 0", "positions",
         [r">=\s*1|at least 1|positive"]),
    case("positions", F, "positions = 13", "positions = -3", "positions",
         [r">=\s*1|at least 1|positive", r"-3"]),
    # ---- branch other than +1/-1
    case("branch", F, "branch  = -1", "branch  = 0", "branch", [r"\+1", r"-1", r"got 0|\b0\b"]),
    case("branch", F, "branch  = -1", "branch  = 2", "branch", [r"\+1", r"-1", r"\b2\b"]),
    case("branch", S, "branch = -1", "branch = -2", "branch", [r"\+1", r"-1", r"-2"]),
    # ---- unknown keys (typos)
    case("unknown key", F, "length   = 0.14", "lenght   = 0.14", "lenght", [r"unknown", r"length"]),
    case("unknown key", F, "branch  = -1", "brnach  = -1", "brnach", [r"unknown", r"branch"],
         id="brnach (the missing branch must not be reported first)"),
    case("unknown key", F, "along = 0.2129", "alng = 0.2129", "alng", [r"unknown", r"along"]),
    case("unknown key", F, 'title  = "Crank-rocker four-bar"', 'titel  = "Crank-rocker four-bar"',
         "titel", [r"unknown", r"title"]),
    case("unknown key", F, "lengths = [0.5, 0.34]", "length = 0.5", "length",
         [r"unknown", r"lengths"], id="RRR given length instead of lengths"),
    case("unknown key", S, 'joints = ["A", "B"]', 'joints = ["A", "B"]\nbranch = 1', "branch",
         [r"unknown", r"offset"], anchor="branch = 1", id="RPR given a branch"),
    case("unknown key", S, "angle_deg = 0.0", "angle = 0.0", "angle", [r"unknown", r"angle_deg"],
         anchor="guide  ="),
    case("unknown key", F, "[[group]]               # g1", "[[groups]]              # g1", "groups",
         [r"unknown", r"\bgroup\b"],
         id="[[groups]] table header typo"),
    # ---- wrong `links` numbering
    case("links", F, "links   = [2, 3]", "links   = [3, 4]", "links", [r"\[2, 3\]", r"\[3, 4\]"]),
    case("links", F, "links   = [2, 3]", "links   = [1, 2]", "links", [r"\[2, 3\]"]),
    case("links", F, "links   = [2, 3]", "links   = [2, 2]", "links", [r"\[2, 3\]"]),
    case("links", S, "links  = [4, 5]", "links  = [2, 3]   # again", "links",
         [r"\[4, 5\]", r"\[2, 3\]"]),
    case("links", S, "links  = [4, 5]", "links  = [5, 4]", "links", [r"\[4, 5\]"]),
    # ---- `from` not a joint of the point's link; a point on a link that does not exist
    case("from", F, 'from   = "A"', 'from   = "O1"', "from", [r"'O1'", r"link 2", r"\bA\b", r"\bB\b"]),
    case("from", F, 'from  = "O1"', 'from  = "A"', "from", [r"'A'", r"link 3", r"\bO1\b"]),
    case("from", F, 'from   = "A"', 'from   = "S3"', "from", [r"'S3'", r"link 2"],
         id="S2 measured from S3 (on link 3)"),
    case("from", S, 'from  = "B"', 'from  = "O"', "from", [r"'O'", r"link 3"],
         id="C (needed by group 2) measured from O, not on link 3"),
    case("from", F, "link   = 2", "link   = 9", "link", [r"\b9\b", r"\b3\b"]),
    case("from", F, "link   = 2", "link   = 0", "link", [r"\b0\b", r"moving|1"]),
    # ---- the crank's pivot, a guide's `through`
    case("unknown point", F, 'pivot    = "O"', 'pivot    = "Q"', "pivot", [r"'Q'", r"frame point"]),
    case("unknown point", S, "through = [0.0, 0.47]", 'through = "Z"', "through",
         [r"'Z'", r"frame point", r"\bB\b", r"\bO\b"], anchor="guide  ="),
    case("unknown point", S, "through = [0.0, 0.47]", 'through = "D"', "through",
         [r"'D'", r"frame point"], anchor="guide  =", id="guide through the moving joint D"),
]


@pytest.mark.parametrize("base, old, new, key, expects, anchor", CASES)
def test_mistake_gives_one_line_naming_file_line_key_and_expectation(
        tmp_path, base, old, new, key, expects, anchor):
    text = mutate(base, old, new)
    path = write(tmp_path, text)
    msg = scene_error(path)
    assert_one_line(msg)
    line = line_of(text, anchor)
    assert msg.startswith(f"{path}:{line}: "), f"expected '{path}:{line}: ...', got: {msg}"
    assert_mentions(msg[len(f"{path}:{line}: "):], key, expects)


SUBTABLE_GUIDE = ("guide  = { through = [0.0, 0.47], angle_deg = 0.0 }\nbranch = -1\n",
                  'branch = -1\n[group.guide]\nthrough = "Z"\nangle_deg = 0.0\n')


def test_guide_as_subtable_through_unknown_point_is_found(tmp_path):
    """`[group.guide]` is the same TOML as `guide = {...}`: the mistake must still be found."""
    msg = scene_error(write(tmp_path, mutate(SHAPER, *SUBTABLE_GUIDE)))
    assert_one_line(msg)
    assert_mentions(msg, "through", [r"'Z'", r"frame point"])


def test_guide_as_subtable_through_unknown_point_names_its_line(tmp_path):
    text = mutate(SHAPER, *SUBTABLE_GUIDE)
    path = write(tmp_path, text)
    msg = scene_error(path)
    line = line_of(text, 'through = "Z"')
    assert msg.startswith(f"{path}:{line}: "), msg


@pytest.mark.parametrize("old, new, anchor", [
    ('title  = "Crank-rocker four-bar"', 'title  = "Crank-rocker four-bar', "title  ="),
    ("length   = 0.14", "length   = 0.14 0.2", "length   ="),
    ("omega    = 20.0", "omega    = 20,0", "omega    ="),
    ('joints  = ["A", "B", "O1"]', 'joints  = ["A", "B" "O1"]', "joints  ="),
    ("along = 0.2129", "along = .2129", "along ="),
    ("[[point]]               # pS3", "[[point]               # pS3", "# pS3"),
    ("O1 = [0.0, -0.53]", "O1 = [0.0, -0.53]\nO1 = [0.0, 0.0]", "O1 = [0.0, 0.0]"),
], ids=["unterminated string", "two values", "decimal comma", "missing comma",
        "leading dot", "unclosed header", "duplicate key"])
def test_toml_syntax_error_gives_file_and_line(tmp_path, old, new, anchor):
    text = mutate(FOURBAR, old, new)
    path = write(tmp_path, text)
    msg = scene_error(path)
    assert_one_line(msg)
    line = line_of(text, anchor)
    assert msg.startswith(f"{path}:{line}: "), f"expected '{path}:{line}: ...', got: {msg}"
    assert "TOML" in msg
    assert "column" not in msg.split(": ", 1)[0]


@pytest.mark.parametrize("old, key", [
    ('[frame]                 # fixed points\nO  = [0.0, 0.0]\nO1 = [0.0, -0.53]\n', "frame"),
    ('[crank]                 # link 1\npivot    = "O"\njoint    = "A"\nlength   = 0.14\n'
     'phi0_deg = 0.0\nstep_deg = 30.0\npositions = 13\nomega    = 20.0\nepsilon  = 0.0\n', "crank"),
])
def test_missing_table_names_file_and_table(tmp_path, old, key):
    path = write(tmp_path, mutate(FOURBAR, old, ""))
    msg = scene_error(path)
    assert_one_line(msg)
    assert msg.startswith(f"{path}:") or msg.startswith(f"{path} ")
    assert_mentions(msg, key, [r"missing"])


def test_empty_frame_table(tmp_path):
    text = mutate(FOURBAR, "O  = [0.0, 0.0]\nO1 = [0.0, -0.53]\n", "")
    path = write(tmp_path, text)
    msg = scene_error(path)
    assert_one_line(msg)
    assert msg.startswith(f"{path}:{line_of(text, '# fixed points')}: ")
    assert "frame" in msg and re.search(r"at least one|point", msg)


def test_missing_file(tmp_path):
    path = tmp_path / "no_such_scene.toml"
    msg = scene_error(path)
    assert_one_line(msg)
    assert msg.startswith(str(path))
    assert re.search(r"no such file|not found|does not exist", msg, re.I)


def test_directory_instead_of_file(tmp_path):
    path = tmp_path / "scene.toml"
    path.mkdir()
    msg = scene_error(path)
    assert_one_line(msg)
    assert msg.startswith(str(path))
    assert "directory" in msg and ".toml" in msg


def test_non_utf8_file(tmp_path):
    path = tmp_path / "latin1.toml"
    path.write_bytes(FOURBAR.replace("Student, group", "Müller, Gruppe").encode("latin-1"))
    msg = scene_error(path)
    assert_one_line(msg)
    assert msg.startswith(str(path))
    assert "UTF-8" in msg


def test_binary_file(tmp_path):
    path = tmp_path / "scene.toml"
    path.write_bytes(b"\x89PNG\r\n\x1a\n\x00\x00\x00\rIHDR\xff\xfe")
    msg = scene_error(path)
    assert_one_line(msg)
    assert msg.startswith(str(path))


def test_scene_error_is_a_value_error():
    assert issubclass(SceneError, ValueError)


# --------------------------------------------------------------------------- valid scenes
@pytest.mark.parametrize("path", sorted(WORKBOOKS.glob("*.toml")), ids=lambda p: p.name)
def test_bundled_scenes_load(path):
    scene = load_scene(path)
    assert isinstance(scene, Scene)
    assert scene.title and scene.title != path.stem        # all bundled scenes have a title
    assert scene.source == str(path)
    kinds = [kind for kind, _ in scene.plan]
    assert kinds[0] == "crank" and kinds.count("crank") == 1
    assert [item for kind, item in scene.plan if kind == "group"] == list(scene.groups)
    assert sorted(item.name for kind, item in scene.plan if kind == "point") == \
        sorted(p.name for p in scene.points)
    assert scene.links == list(range(2, 2 + 2 * len(scene.groups)))
    assert len(scene.crank_angles_deg()) == scene.crank.positions


def test_bundled_scenes_exist():
    names = {p.name for p in WORKBOOKS.glob("*.toml")}
    assert {"fourbar.toml", "shaper.toml", "slotted_lever.toml"} <= names


def test_spec_fourbar_values(tmp_path):
    scene = load_scene(write(tmp_path, FOURBAR, "fourbar.toml"))
    assert scene.title == "Crank-rocker four-bar"
    assert scene.author == "Student, group"
    assert scene.frame == {"O": (0.0, 0.0), "O1": (0.0, -0.53)}
    c = scene.crank
    assert (c.pivot, c.joint, c.length, c.phi0_deg, c.step_deg, c.positions, c.omega, c.epsilon) \
        == ("O", "A", 0.14, 0.0, 30.0, 13, 20.0, 0.0)
    (g,) = scene.groups
    assert (g.index, g.type, g.links, g.joints, g.lengths, g.branch) == \
        (1, "RRR", (2, 3), ("A", "B", "O1"), (0.5, 0.34), -1)
    assert kind_of(g).new_joints(g) == ["B"] and kind_of(g).sliders(g) == []
    assert g.label == "group 1 (RRR A-B-O1)"
    s2, s3 = scene.points
    assert (s2.name, s2.link, s2.origin, s2.along, s2.across) == ("S2", 2, "A", 0.39035, 0.0)
    assert (s3.name, s3.link, s3.origin, s3.along, s3.across) == ("S3", 3, "O1", 0.2129, 0.0)
    assert scene.moving_joints == ["A", "B"]
    assert scene.sliders == []
    assert scene.crank_angles_deg() == pytest.approx([30.0 * i for i in range(13)])


def test_parse_scene_equals_load_scene(tmp_path):
    path = write(tmp_path, FOURBAR, "fourbar.toml")
    assert parse_scene(FOURBAR, str(path)) == load_scene(path)


MINIMAL = """\
[frame]
O  = [0.0, 0.0]
O1 = [0.0, -0.53]
Q  = [1.0, 0.0]

[crank]
pivot  = "O"
joint  = "A"
length = 0.14
omega  = 20.0

[[group]]
type    = "RRR"
links   = [2, 3]
joints  = ["A", "B", "O1"]
lengths = [0.5, 0.34]
branch  = 1

[[group]]
type   = "RPR"
links  = [4, 5]
joints = ["B", "Q"]

[[point]]
name = "P"
link = 3
from = "O1"
"""


def test_defaults(tmp_path):
    scene = load_scene(write(tmp_path, MINIMAL, "my_linkage.toml"))
    assert scene.title == "my_linkage"            # title defaults to the file's stem
    assert scene.author == ""
    assert scene.crank.epsilon == 0.0
    assert scene.groups[1].offset == 0.0
    (p,) = scene.points
    assert p.along == 0.0 and p.across == 0.0
    assert scene.groups[0].branch == 1
    assert scene.sliders == ["B"]                 # RPR's slider is its J1


def test_title_default_uses_stem_of_given_path(tmp_path):
    (tmp_path / "sub").mkdir()
    scene = load_scene(write(tmp_path / "sub", MINIMAL, "crank.rocker.toml"))
    assert scene.title == "crank.rocker"


def test_explicit_values_override_defaults(tmp_path):
    text = (MINIMAL.replace('omega  = 20.0', 'omega  = 20.0\nepsilon = -3.5')
            .replace('joints = ["B", "Q"]', 'joints = ["B", "Q"]\noffset = 0.05')
            .replace('from = "O1"', 'from = "O1"\nalong = 0.1\nacross = -0.02'))
    scene = load_scene(write(tmp_path, 'title = "x"\n' + text))
    assert scene.title == "x"
    assert scene.crank.epsilon == -3.5
    assert scene.groups[1].offset == 0.05
    assert (scene.points[0].along, scene.points[0].across) == (0.1, -0.02)


def plan_names(scene):
    return [("crank" if kind == "crank" else
             f"group {item.index}" if kind == "group" else f"point {item.name}")
            for kind, item in scene.plan]


SHAPER_PLAN = ["crank", "group 1", "point C", "group 2"]


def test_shaper_plan_places_point_between_groups(tmp_path):
    assert plan_names(load_scene(write(tmp_path, SHAPER))) == SHAPER_PLAN


def test_shaper_plan_does_not_depend_on_file_order(tmp_path):
    point = '[[point]]               # pC\nname  = "C"\nlink  = 3\nfrom  = "B"\nalong = 0.49\n\n'
    without = mutate(SHAPER, point, "")
    at_end = without + "\n" + point
    at_start = mutate(without, "[[group]]               # g1", point + "[[group]]               # g1")
    for text in (at_end, at_start):
        assert plan_names(load_scene(write(tmp_path, text))) == SHAPER_PLAN


def test_point_measured_from_a_later_declared_point_of_its_link(tmp_path):
    """A point may be measured from another point of its link, whatever their file order."""
    text = mutate(FOURBAR, "[[point]]               # pS2",
                  '[[point]]\nname = "T"\nlink = 3\nfrom = "S3"\nacross = 0.05\n\n'
                  "[[point]]               # pS2")
    scene = load_scene(write(tmp_path, text))
    names = plan_names(scene)
    assert names.index("point S3") < names.index("point T")
    assert names.index("group 1") < names.index("point S2")


def test_bundled_shaper_plan():
    assert plan_names(load_scene(WORKBOOKS / "shaper.toml")) == SHAPER_PLAN


def test_guide_through_a_frame_point(tmp_path):
    text = mutate(SHAPER, "through = [0.0, 0.47]", 'through = "B"').replace(
        "angle_deg = 0.0", "angle_deg = 90.0")
    g2 = load_scene(write(tmp_path, text)).groups[1]
    assert g2.guide.point == (0.0, 0.0) and g2.guide.angle_deg == 90.0 and g2.guide.link == 0
    assert kind_of(g2).sliders(g2) == ["D"] and kind_of(g2).new_joints(g2) == ["D"]


# ---- messages made clearer after review (each names the key and what is expected)
@pytest.mark.parametrize("old, new, line_key, expects", [
    ('type    = "RRR"\n', "", "links", [r"missing", r"RRR, RRP, RPR"]),
    ("omega    = 20.0", "omega    = inf", "omega", [r"finite number", r"inf"]),
    ("epsilon  = 0.0", "epsilon  = nan", "epsilon", [r"finite number", r"nan"]),
    ('joints  = ["A", "B", "O1"]', 'joints  = ["A", "A", "O1"]', "joints", [r"must differ", r"'A'"]),
], ids=["missing type", "omega inf", "epsilon nan", "new joint equals J1"])
def test_clearer_messages(tmp_path, old, new, line_key, expects):
    text = mutate(FOURBAR, old, new)
    msg = scene_error(write(tmp_path, text))
    assert_one_line(msg)
    key = "type" if line_key == "links" else line_key
    assert f"'{key}'" in msg, msg
    for pattern in expects:
        assert re.search(pattern, msg), f"{pattern!r} not in {msg!r}"


def test_byte_order_mark_is_accepted(tmp_path):
    """Windows Notepad saves UTF-8 with a BOM; the scene is still valid TOML after it."""
    path = tmp_path / "bom.toml"
    path.write_bytes(b"\xef\xbb\xbf" + FOURBAR.encode("utf-8"))
    assert load_scene(path).crank.length == 0.14
