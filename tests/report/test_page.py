"""The report's page (usvtool/report/document.py's placements, usvtool/report/page.py): the main
body, then the appendix; what is placed ``html`` folded in the screen page and absent from the
print page the PDF is laid out from; the contents after the summary."""

from __future__ import annotations

import re
import struct
import zlib

import pytest

from usvtool.report.document import APPENDIX, HTML, Cell, Figure, Section, Table, layout
from usvtool.report.page import html, pdf, png_width_mm


def table(name: str, placement: str = "main") -> Table:
    return Table(name, name.upper(), "a caption", ["a"], [[Cell("1")]], placement)


def document() -> list[Section]:
    return [
        Section("summary", "Summary", ["first"], [table("s1")]),
        Section("one", "One", ["text"], [table("t1"), table("t1-later", APPENDIX),
                                         table("t1-web", HTML)],
                [Section("one-a", "One A", blocks=[table("ta")]),
                 Section("one-b", "One B", blocks=[table("tb")], placement=APPENDIX)]),
        Section("two", "Two", blocks=[table("t2")], placement=APPENDIX),
        Section("three", "Three", blocks=[table("t3")], placement=HTML),
    ]  # fmt: skip


def ids(page: str) -> list[str]:
    return re.findall(r'id="([^"]+)"', page)


def test_layout_moves_appendix_parts_after_the_main_body_and_keeps_the_rest():
    main, appendix = layout(document())
    assert [s.id for s in main] == ["summary", "one", "three"]
    assert [b.id for b in main[1].blocks] == ["t1", "t1-web"]
    assert [s.id for s in main[1].subsections] == ["one-a"]
    assert [s.id for s in appendix] == ["one-appendix", "two"]
    assert appendix[0].title == "One"  # the main section's title, continued in the appendix
    assert [b.id for b in appendix[0].blocks] == ["t1-later"]
    assert [s.id for s in appendix[0].subsections] == ["one-b"]


def test_the_screen_page_has_the_appendix_last_and_html_only_parts_folded():
    page = html("T", "sub", document())
    order = ids(page)
    body = order.index("appendix")
    assert {"t1", "ta", "t1-web", "three", "t3"} <= set(order[:body])
    assert order[body:] == ["appendix", "one-appendix", "t1-later", "one-b", "tb", "two", "t2"]
    folded = re.findall(r'<details class="html-only"><summary>([^<]+)</summary>\s*'
                        r'<(\w+)[^>]*? id="([^"]+)"', page)  # fmt: skip
    assert folded == [("T1-WEB", "div", "t1-web"), ("Three", "section", "three")]


def test_the_print_page_leaves_the_html_only_parts_out():
    page = html("T", "sub", document(), "print")
    assert "<details" not in page and "t1-web" not in page and 'id="three"' not in page
    assert ids(page).index("t1") < ids(page).index("appendix") < ids(page).index("t1-later")


def test_the_contents_follow_the_summary_not_page_one():
    for medium in ("screen", "print"):
        page = html("T", "sub", document(), medium)
        summary, toc, one = (page.index(s) for s in ('id="summary"', 'class="toc"', 'id="one"'))
        assert summary < toc < one
    page = html("T", "sub", document()[1:])  # no summary: the contents first
    assert page.index('class="toc"') < page.index('id="one"')


def test_an_unknown_placement_is_refused_naming_the_block():
    with pytest.raises(ValueError, match="one: t9: placement 'pdf'"):
        layout([Section("one", "One", blocks=[table("t9", "pdf")])])


def png(width: int, per_metre: int | None, height: int = 1) -> bytes:
    def chunk(name: bytes, data: bytes) -> bytes:
        return struct.pack(">I", len(data)) + name + data + struct.pack(
            ">I", zlib.crc32(name + data))  # fmt: skip

    head = chunk(b"IHDR", struct.pack(">IIBBBBB", width, height, 8, 0, 0, 0, 0))
    phys = chunk(b"pHYs", struct.pack(">IIB", per_metre, per_metre, 1)) if per_metre else b""
    pixels = chunk(b"IDAT", zlib.compress((b"\0" + b"\xff" * width) * height))
    return b"\x89PNG\r\n\x1a\n" + head + phys + pixels + chunk(b"IEND", b"")


def test_a_figure_prints_at_its_own_resolution():
    # 150 dpi = 5905.5 px/m (the PNG stores 5906): 1050 px are 7 in = 177.8 mm
    assert png_width_mm(png(1050, 5906)) == 177.8
    assert png_width_mm(png(1050, None)) is None
    figure = Figure("f", "F", "c", png(1050, 5906), "x\n1\n")
    page = html("T", "s", [Section("one", "One", blocks=[figure])], "print")
    assert 'style="width: 177.8mm"' in page
    assert "style=" not in html("T", "s", [Section("one", "One", blocks=[figure])]).split(
        "</style>")[1]  # fmt: skip


@pytest.mark.slow  # two WeasyPrint layouts
def test_the_pdf_keeps_a_heading_with_its_figure_and_counts_the_main_body_up_to_the_appendix():
    """A figure 199.8 mm tall (1180 px at 150 dpi) does not fit below the title, summary and
    contents (A4: 265 mm of text height), so it starts page 2, its section's heading with it;
    the appendix starts page 3."""
    weasyprint = pytest.importorskip("weasyprint")
    tall = Figure("tall", "Tall", "c", png(1050, 5906, height=1180), "x\n1\n")
    sections = [Section("summary", "Summary", ["first"]),
                Section("one", "One", ["text"], [tall]),
                Section("two", "Two", blocks=[table("t9")], placement=APPENDIX)]  # fmt: skip
    page = html("T", "s", sections, "print")
    anchors = [set(p.anchors) for p in weasyprint.HTML(string=page).render().pages]
    assert [("summary" in a, "one" in a, "tall" in a, "appendix" in a) for a in anchors] == [
        (True, False, False, False), (False, True, True, False), (False, False, False, True)]
    _, pages, main = pdf(page)
    assert (pages, main) == (3, 2)
    _, pages, main = pdf(html("T", "s", sections[:2], "print"))
    assert (pages, main) == (2, 2)  # no appendix: every page is the main body's
