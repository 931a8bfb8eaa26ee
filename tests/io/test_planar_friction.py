"""Friction keys on ``[[joint]]`` of a planar file (docs/friction.md): read with their units
into the engine's joints, keys of another joint type and bad values refused with the key named.
"""

from pathlib import Path

import pytest

from linkwork import io
from linkwork.errors import LinkworkError
from linkwork.planar import PinInSlot, Prismatic, Revolute

EXAMPLE = Path(__file__).resolve().parents[2] / "examples" / "sine_press_planar.toml"


def with_keys(tmp_path: Path, crank: str = "", guide: str = "", slot: str = "") -> Path:
    """The sine press example with lines added to its joints A (revolute), guide
    (prismatic) and slot."""
    text = EXAMPLE.read_text()
    for name, extra in (("A", crank), ("guide", guide), ("slot", slot)):
        i = text.index(f'name = "{name}"')
        j = text.index("\n", text.index("b = ", i)) + 1
        text = text[:j] + extra + text[j:]
    f = tmp_path / "m.toml"
    f.write_text(text)
    return f


def test_friction_keys_with_units(tmp_path):
    f = with_keys(tmp_path, crank='friction = 0.05\nradius = "30 mm"\n'
                  'friction_torque = "0.5 N*m"\n',
                  guide='friction = 0.1\nlength = "0.2 m"\n',
                  slot='friction = "12 %"\nradius = "8 mm"\n')
    mech = io.load(f).mechanism()
    a, guide, slot = (mech.joint(n) for n in ("A", "guide", "slot"))
    assert isinstance(a, Revolute) and isinstance(guide, Prismatic)
    assert isinstance(slot, PinInSlot)
    assert (a.friction, a.radius, a.friction_torque) == pytest.approx((0.05, 0.03, 0.5))
    assert (guide.friction, guide.length) == pytest.approx((0.1, 0.2))
    assert (slot.friction, slot.radius) == pytest.approx((0.12, 0.008))


def test_no_friction_keys_no_friction():
    mech = io.load(EXAMPLE).mechanism()
    assert not any(j.has_friction for j in mech.joints)


@pytest.mark.parametrize(("kw", "match"), [
    ({"crank": 'length = "10 mm"\n'}, r"length.*revolute"),
    ({"guide": 'radius = "10 mm"\n'}, r"radius.*prismatic"),
    ({"slot": 'friction_torque = 1\n'}, r"friction_torque.*slot"),
    ({"slot": "friction = -0.1\n"}, r"joint\.2\.friction \(slot\): -0\.1 is invalid.*>= 0"),
    ({"guide": "friction = 1.5\n"}, r"joint\.1\.friction \(guide\): 1\.5 is invalid.*< 1"),
    ({"crank": "friction = 0.1\n"}, r"joint\.0\.radius \(A\): is required here: must be "
     r"> 0 \[m\] \(the journal radius of a joint with friction\)"),
    ({"crank": 'friction = 0.1\nradius = "60 mm"\n'},
     r"joint\.0\.radius \(A\): 60 mm is invalid.*< 0\.05 m.*crank"),
    ({"guide": 'friction = 0.1\nlength = "-1 mm"\n'},
     r"joint\.1\.length \(guide\): -1 mm is invalid"),
    ({"crank": 'friction = 0.1\nradius = "30 kg"\n'}, r"radius.*length"),
])
def test_bad_friction_keys(tmp_path, kw, match):
    with pytest.raises(LinkworkError, match=match):
        io.load(with_keys(tmp_path, **kw))
