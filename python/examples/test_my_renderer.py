"""Test your renderer against the reference — a pytest example.

Replace `my_renderer` with yours: it gets a splatref.Scene (model, camera,
algorithm and options, exactly as the command line and scene files give
them; scene.info has its size) and returns the picture it made, an
(H, W, 3) array of uint8, uint16 or float32 values with row 0 at the top.
splatref.check compares it with the CPU reference under PARITY.md's tiers
and says which pixels fail.

Here the renderer under test is splatref's own GL backend (on the machine's
OpenGL driver: llvmpipe, or a GPU's), which must match the reference bit
for bit; a renderer of your own would start at Tier B (tier="B", lsb=1).

    python3 -m pytest python/examples/test_my_renderer.py
"""
import pytest
import splatref as sr

SCENES = {
    "deferred, Voronoi depth": dict(model="builtin:torus", points=6000, size=(128, 96), algo="deferred", voronoi=True, groups="mgc"),
    "two-pass baseline": dict(model="builtin:sphere", points=5000, size=(96, 96), algo="pbr2p1"),
    "transparency": dict(model="builtin:spheres", points=4000, size=(96, 96), algo="transparent1", alpha=0.5),
}


def my_renderer(scene):
    """Your renderer goes here."""
    frame = scene.render(backend="gl")
    return sr.to_u8(frame.image[:, :, :3])  # 8-bit RGB, as a PNG would hold it


@pytest.mark.parametrize("name", sorted(SCENES))
def test_matches_the_reference(name):
    with sr.Scene(**SCENES[name]) as scene:
        try:
            image = my_renderer(scene)
        except sr.NoDevice as e:
            pytest.skip("no GL device here: %s" % e)
        result = sr.check(image, scene)  # Tier A: bit-exact
        assert result, result.summary()


def test_a_wrong_pixel_is_named():
    """What a failure looks like: one value one LSB off."""
    with sr.Scene(**SCENES["two-pass baseline"]) as scene:
        image = sr.to_u8(scene.render().image[:, :, :3])
        image[40, 50, 0] ^= 1
        result = sr.check(image, scene)
        assert not result
        assert result.failing == [(50, scene.height - 1 - 40)]  # (x, y from the bottom)
        assert sr.check(image, scene, tier="B", lsb=1)  # within one LSB
