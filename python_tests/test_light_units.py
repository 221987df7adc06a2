"""bakegi.light_units against the physics and Cycles' conventions (CYCLES_FACTS.md)."""

import math

import pytest

from bakegi import light_units as lu

IDENTITY = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 1, 2], [0, 0, 0, 1]]


def test_a_lambertian_emitter_of_power_p_has_radiance_p_over_pi_a_in_cycles_4():
    # Exitance M = pi L for a Lambertian surface, so P = pi L A: Cycles 4.0+ is physical.
    assert lu.area_radiance((1, 1, 1), 100.0, 2.0, (4, 2))[0] == pytest.approx(100.0 / (math.pi * 2.0))
    # Cycles 3.x divides by 4 instead of pi: 4/pi = 1.273x darker (measured in the tests).
    assert lu.area_radiance((1, 1, 1), 100.0, 2.0, (3, 4))[0] == pytest.approx(100.0 / 8.0)


def test_shape_areas():
    assert lu.area_of_shape("SQUARE", 2.0, 9.0) == 4.0
    assert lu.area_of_shape("RECTANGLE", 2.0, 3.0) == 6.0
    assert lu.area_of_shape("DISK", 2.0, 9.0) == pytest.approx(math.pi)
    assert lu.area_of_shape("ELLIPSE", 2.0, 4.0) == pytest.approx(2.0 * math.pi)


def test_a_point_light_spreads_its_power_over_the_sphere():
    light = lu.BlenderLight("lamp", "POINT", (1.0, 0.5, 0.0), 4 * math.pi, IDENTITY)
    core = lu.convert_light(light).light
    assert core.color == pytest.approx((1.0, 0.5, 0.0))  # W/sr
    assert core.position == (0.0, 0.0, 2.0)
    assert core.direction == (0.0, 0.0, -1.0)


def test_exposure_doubles_the_power_per_stop():
    base = lu.convert_light(lu.BlenderLight("a", "POINT", (1, 1, 1), 10.0, IDENTITY)).light
    brighter = lu.convert_light(
        lu.BlenderLight("a", "POINT", (1, 1, 1), 10.0, IDENTITY, exposure=1.5)).light
    assert brighter.color[0] == pytest.approx(base.color[0] * 2 ** 1.5)


def test_blackbody_colours_have_unit_luminance_and_the_right_tint():
    for kelvin in (1500, 3200, 6500, 12000):
        r, g, b = lu.blackbody_color(kelvin)
        assert 0.2126 * r + 0.7152 * g + 0.0722 * b == pytest.approx(1.0)
    warm, white, cold = lu.blackbody_color(2000), lu.blackbody_color(6500), lu.blackbody_color(12000)
    assert warm[0] > warm[1] > warm[2]
    assert cold[2] > cold[0]
    # A 6500 K black body is close to, not exactly, D65 white.
    assert max(white) / min(white) < 1.15


def test_a_light_that_cannot_be_placed_or_emits_nothing_is_left_out():
    flat = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 2], [0, 0, 0, 1]]
    conversion = lu.convert_light(lu.BlenderLight("flat", "SPOT", (1, 1, 1), 10.0, flat))
    assert conversion.light is None and "zero scale" in conversion.warnings[0]
    dark = lu.convert_light(lu.BlenderLight("dark", "SUN", (0, 0, 0), 3.0, IDENTITY))
    assert dark.light is None and dark.warnings == []
    nan = lu.convert_light(lu.BlenderLight("nan", "AREA", (1, 1, 1), float("nan"), IDENTITY))
    assert nan.light is None and "not finite" in nan.warnings[0]


def test_a_light_node_tree_tints_the_colour_and_an_unreadable_one_warns():
    base = lu.convert_light(lu.BlenderLight("a", "POINT", (1, 1, 1), 10.0, IDENTITY)).light
    tinted = lu.convert_light(lu.BlenderLight("a", "POINT", (1, 1, 1), 10.0, IDENTITY,
                                              use_nodes=True, node_tint=(2.0, 1.0, 0.5)))
    assert tinted.light.color == pytest.approx(tuple(c * t for c, t in
                                                     zip(base.color, (2.0, 1.0, 0.5))))
    assert not tinted.warnings
    unread = lu.convert_light(lu.BlenderLight("a", "POINT", (1, 1, 1), 10.0, IDENTITY,
                                              use_nodes=True, node_tint=None))
    assert unread.light.color == pytest.approx(base.color)
    assert any("shader nodes are ignored" in w for w in unread.warnings)


def test_cast_shadow_off_sets_the_core_flag_on_every_type():
    for kind in ("POINT", "SPOT", "SUN", "AREA"):
        light = lu.BlenderLight("a", kind, (1, 1, 1), 10.0, IDENTITY, size=1.0, size_y=1.0,
                                cast_shadow=False)
        assert lu.convert_light(light).light.flags & lu.NO_SHADOW, kind
        light.cast_shadow = True
        assert not lu.convert_light(light).light.flags & lu.NO_SHADOW, kind


def test_a_portal_keeps_the_area_lights_shape_and_emits_nothing():
    light = lu.BlenderLight("window", "AREA", (1, 1, 1), 1000.0, IDENTITY, shape="RECTANGLE",
                            size=2.0, size_y=1.5, is_portal=True)
    portal = lu.convert_portal(light)
    assert portal.light.color == (0.0, 0.0, 0.0)
    assert (portal.light.size_x, portal.light.size_y) == (2.0, 1.5)
    assert portal.light.direction == (0.0, 0.0, -1.0)
    flat = [[1, 0, 0, 0], [0, 1, 0, 0], [0, 0, 0, 2], [0, 0, 0, 1]]  # zero scale along z
    light.matrix_world = flat
    gone = lu.convert_portal(light)
    assert gone.light is None and any("portal 'window'" in w for w in gone.warnings)


def test_an_area_spread_below_180_degrees_goes_to_the_core():
    light = lu.BlenderLight("box", "AREA", (1, 1, 1), 100.0, IDENTITY, size=1.0,
                            spread=math.radians(45.0))
    converted = lu.convert_light(light)
    assert converted.light.spot_size == pytest.approx(math.radians(45.0))
    assert not converted.warnings
    light.spread = math.pi
    assert lu.convert_light(light).light.spot_size == 0.0  # Lambertian
    light.spread = 0.0
    narrow = lu.convert_light(light)
    assert narrow.light.spot_size == pytest.approx(lu.MIN_SPREAD)
    assert any("baked as 1 deg" in w for w in narrow.warnings)
