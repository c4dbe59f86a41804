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
