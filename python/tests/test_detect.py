"""kincal.detect: a target found in images from Python, as the program finds it (images drawn
here as PGM files: the test needs no OpenCV of its own)."""

import subprocess
from pathlib import Path

import pytest

import kincal


def write_board(path: Path, square: int) -> None:
    """A chessboard of 6 x 8 squares of `square` px (5 x 7 inner corners) on a white page."""
    left, top = 320 - 4 * square, 240 - 3 * square
    pixels = bytearray()
    for y in range(480):
        for x in range(640):
            on = left <= x < left + 8 * square and top <= y < top + 6 * square
            black = on and ((x - left) // square + (y - top) // square) % 2 == 0
            pixels.append(0 if black else 255)
    path.write_bytes(b"P5\n640 480\n255\n" + bytes(pixels))


def built_with_opencv() -> bool:
    try:
        kincal.detect("chessboard:5x7:20mm", "/nonexistent/V.csv", images="/nonexistent")
    except kincal.KincalError as e:
        return "needs OpenCV" not in str(e)
    return True


def test_detect_writes_the_programs_table_and_reports_each_image(tmp_path: Path, program: str) -> None:
    if not built_with_opencv():
        with pytest.raises(kincal.KincalError, match="needs OpenCV"):
            kincal.detect("chessboard:5x7:20mm", tmp_path / "V.csv", images=tmp_path)
        return
    write_board(tmp_path / "a.pgm", 40)
    write_board(tmp_path / "b.pgm", 30)
    (tmp_path / "c.pgm").write_text("not an image")
    (tmp_path / "poses.csv").write_text("image,joint1_deg\na.pgm,1\nb.pgm,2\nc.pgm,3\n")
    report = kincal.detect("chessboard:5x7:20mm", tmp_path / "V.csv", poses=tmp_path / "poses.csv",
                           json=tmp_path / "detect.json")
    assert report["found"] == 2 and report["total"] == 3
    assert [image["status"] for image in report["images"]] == ["found", "found", "unreadable"]
    assert report.csv == (tmp_path / "V.csv").read_text()
    assert "2 of 3 images with the target" in report.text
    subprocess.run([program, "detect", "--target", "chessboard:5x7:20mm", "--poses",
                    str(tmp_path / "poses.csv"), "--out", str(tmp_path / "P.csv")], check=True,
                   stdout=subprocess.DEVNULL)
    assert (tmp_path / "P.csv").read_text() == report.csv


def test_detect_refuses_bad_input_in_one_line(tmp_path: Path) -> None:
    if not built_with_opencv():
        pytest.skip("kincal was built without OpenCV (the other test checks what it says)")
    with pytest.raises(kincal.KincalError, match="target 'chessboard:5x7'"):
        kincal.detect("chessboard:5x7", tmp_path / "V.csv", images=tmp_path)
    (tmp_path / "poses.csv").write_text("image,joint1\nmissing.pgm,1\n")
    with pytest.raises(kincal.KincalError, match="missing.pgm': no such file"):
        kincal.detect("chessboard:5x7:20mm", tmp_path / "V.csv", poses=tmp_path / "poses.csv")
    assert not (tmp_path / "V.csv").exists()


def test_calibrate_reports_each_camera_view_and_draws_it_on_its_image(tmp_path: Path, program: str) -> None:
    """The reprojection error per view, as the program reports it, and the page drawing each
    view on the image the data's `image` column names (blank frames and a note without it)."""
    model = tmp_path / "M.json"
    subprocess.run([program, "model", "--preset", "ur5-urdf-camera", "--out", str(model)],
                   check=True)
    subprocess.run([program, "simulate", "--model", str(model), "--poses", "6",
                    "--noise-half-width", "0.5px", "--param-error", "0.1mm,0.0005rad",
                    "--validation", "1", "--write-data", str(tmp_path / "sim.csv")],
                   check=True, stdout=subprocess.DEVNULL)
    lines, k = [], 0
    for line in (tmp_path / "sim.csv").read_text().splitlines():
        if not line or line.startswith("#"):
            lines.append(line)
        elif not any(l and not l.startswith("#") for l in lines):
            lines.append("image," + line)
        else:
            lines.append(f"v{k}.pgm,{line}")
            k += 1
    (tmp_path / "views.csv").write_text("\n".join(lines) + "\n")
    (tmp_path / "images").mkdir()
    for i in range(k):
        write_board(tmp_path / "images" / f"v{i}.pgm", 20)
    report = kincal.calibrate(model, tmp_path / "views.csv", noise_std="0.3px", fix=["camera.*"],
                              html=tmp_path / "R.html", images=tmp_path / "images")
    views = report["camera_views"][0]
    assert [v["image"] for v in views["views"]] == [f"v{i}.pgm" for i in range(k)]
    assert abs(views["rms_px"] - 2 ** 0.5 * report["residual_rms"]) < 1e-9 * views["rms_px"]
    assert "reprojection error of camera" in report.text
    html = (tmp_path / "R.html").read_text()
    if built_with_opencv():
        assert html.count("<image ") == k
    else:
        assert html.count("<image ") == 0
        assert any("without OpenCV" in n for n in report.notes)
    blank = kincal.calibrate(model, tmp_path / "views.csv", noise_std="0.3px", fix=["camera.*"],
                             html=tmp_path / "B.html")
    assert (tmp_path / "B.html").read_text().count("<image ") == 0
    if built_with_opencv():
        assert any(f"{k} image(s) named in the data not read" in n for n in blank.notes)
