"""Animated views from Python: the same document the CLI writes, shown inline in Jupyter,
saved as a page or a GIF; bad arguments name themselves."""

import html
import re

import pytest

import telescopic


def test_a_runs_view_is_the_clis_document(cli, tmp_path):
    scene = telescopic.Scene.load("scenes/adams-clearance.toml", set={"time.end": 1.0})
    view = telescopic.simulate(scene).animate(scale=3)
    assert view.frame_count == 51
    page = tmp_path / "cli.html"
    cli("animate", "scenes/adams-clearance.toml", "--set", "time.end=1.0", "--scale", "3",
        "--out", str(page))
    assert view.html == page.read_text()
    # Jupyter shows the same document in a sandboxed frame that runs its script
    shown = view._repr_html_()
    srcdoc = re.search(r'srcdoc="([^"]*)"', shown).group(1)
    assert html.unescape(srcdoc) == view.html
    assert 'sandbox="allow-scripts"' in shown


def test_a_view_saves_as_page_and_gif(tmp_path):
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.4})
    view = telescopic.simulate(scene).animate(fps=10, size=(320, 240))
    assert view.save(tmp_path / "run.html") == len(view.html.encode())
    size = view.save(tmp_path / "run.gif")
    data = (tmp_path / "run.gif").read_bytes()
    assert data[:6] == b"GIF89a" and len(data) == size
    assert int.from_bytes(data[6:8], "little") == 320 and int.from_bytes(data[8:10], "little") == 240
    # one image descriptor per frame: 0.4 s at 10 per second
    assert data.count(b"\x21\xf9\x04") == 5
    with pytest.raises(telescopic.TelescopicError):
        view.save(tmp_path / "run.mp4")
    assert not (tmp_path / "run.mp4").exists()


def test_a_default_views_gif_has_the_clis_frame_rate(cli, tmp_path):
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.4})
    view = telescopic.simulate(scene).animate(size=(320, 240))
    assert view.frame_count == 21  # the page: 50 frames a second
    view.save(tmp_path / "python.gif")
    cli("animate", "scenes/adams-linear.toml", "--set", "time.end=0.4", "--size", "320x240",
        "--out", str(tmp_path / "cli.gif"))
    python = (tmp_path / "python.gif").read_bytes()
    # 0.4 s at the GIF's 25 frames a second, as the CLI writes it
    assert python.count(b"\x21\xf9\x04") == 11
    assert python == (tmp_path / "cli.gif").read_bytes()


def test_the_modes_view_holds_each_mode():
    rig = telescopic.Scene.load("scenes/test-rig.toml")
    view = telescopic.modes(rig, count=4).animate()
    assert view.frame_count == 4
    assert '"kind":"modes"' in view.html and "https://" not in view.html


def test_bad_animation_arguments_name_themselves():
    scene = telescopic.Scene.load("scenes/adams-linear.toml", set={"time.end": 0.2})
    sim = telescopic.simulate(scene)
    for arguments, name in [({"fps": 0.0}, "fps"), ({"scale": float("nan")}, "scale"),
                            ({"size": (10, 10)}, "size"), ({"speed": 1e6}, "speed")]:
        with pytest.raises(telescopic.OptionError) as caught:
            sim.animate(**arguments)
        assert caught.value.option == name, (arguments, caught.value)


def test_saving_through_a_link_onto_the_input_scene_is_refused(tmp_path):
    source = tmp_path / "scene.toml"
    source.write_text(open("scenes/adams-linear.toml").read())
    before = source.read_bytes()
    scene = telescopic.Scene.load(str(source), set={"time.end": 0.2})
    view = telescopic.simulate(scene).animate()
    link = tmp_path / "view.html"
    link.symlink_to(source)
    with pytest.raises(telescopic.TelescopicError, match="is the input"):
        view.save(str(link))
    with pytest.raises(telescopic.TelescopicError, match="is the input"):
        telescopic.modes(scene).animate().save(str(link))
    assert source.read_bytes() == before
