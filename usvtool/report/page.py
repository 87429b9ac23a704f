"""Write the report's document as one self-contained HTML page and as a PDF.

The page embeds everything it shows: figures as ``data:image/png`` URIs, each figure's data as
a ``data:text/csv`` download link (on the screen page: the print page, whose PDF could not
offer it, leaves out its 3 MB), the stylesheet inline, and the runs' players (their data, and
their styles and script once, on the screen only), so it references no file or
address outside itself (the same CSVs are also written beside it). The PDF is the page written
for print (``medium="print"``: what is placed ``html`` left out, the figures at their own
printed size) laid out by WeasyPrint with the stylesheet's print rules; WeasyPrint needs the
Pango system library, and without it the HTML is still written and :func:`pdf` says what to
install.
"""

from __future__ import annotations

import base64
import struct

from markupsafe import Markup

from usvtool.report.document import Section, has_players, layout
from usvtool.report.templating import render

#: What to install when WeasyPrint cannot run.
PDF_HINT = ("install WeasyPrint (pip install weasyprint) and its system libraries (Debian: "
            "apt-get install libpango-1.0-0 libpangoft2-1.0-0)")  # fmt: skip


class PdfUnavailable(Exception):
    """WeasyPrint or its system libraries are missing (the message says which to install)."""


def png_uri(png: bytes) -> str:
    return "data:image/png;base64," + base64.b64encode(png).decode("ascii")


def csv_uri(text: str) -> str:
    return "data:text/csv;base64," + base64.b64encode(text.encode("utf-8")).decode("ascii")


#: The anchor of the appendix's heading (the template's ``<div id="appendix">``).
APPENDIX_ANCHOR = "appendix"


def png_width_mm(png: bytes) -> float | None:
    """The PNG's width at its own resolution (its ``pHYs`` chunk, which Matplotlib writes from
    the figure's dpi), in mm to one decimal; None when it states none in metres."""
    if png[:8] != b"\x89PNG\r\n\x1a\n":
        return None
    width = struct.unpack(">I", png[16:20])[0]
    at = 8
    while at + 8 <= len(png):
        size, name = struct.unpack(">I4s", png[at:at + 8])
        if name == b"pHYs" and size == 9:
            per_metre, _, unit = struct.unpack(">IIB", png[at + 8:at + 17])
            return round(1000 * width / per_metre, 1) if unit == 1 and per_metre else None
        if name in (b"IDAT", b"IEND"):
            return None
        at += 12 + size
    return None


def html(title: str, subtitle: str, sections: list[Section], medium: str = "screen") -> str:
    """The report page for ``medium``: ``screen`` (index.html) or ``print`` (the PDF's). A
    screen page holding a player (:class:`~usvtool.report.document.Player`) holds the players'
    styles and script once (:func:`usvtool.report.animation.embed.assets`); a page without, and
    the print page (no player), neither."""
    main, appendix = layout(sections)
    style = script = ""
    if medium == "screen" and has_players(sections):
        from usvtool.report.animation.embed import assets

        style, script = assets()
    return render("report.html.j2", title=title, subtitle=subtitle, main=main,
                  appendix=appendix, medium=medium, png_uri=png_uri, csv_uri=csv_uri,
                  png_width_mm=png_width_mm, player_style=Markup(style),
                  player_script=Markup(script))  # fmt: skip


def pdf(page: str) -> tuple[bytes, int, int]:
    """The print page as PDF bytes, its number of pages and of the main body's (the pages
    before the one the appendix starts on; all of them without an appendix);
    :class:`PdfUnavailable` without WeasyPrint."""
    try:
        import weasyprint
    except (ImportError, OSError) as e:  # OSError: Pango missing (cffi cannot load it)
        raise PdfUnavailable(f"report.pdf not written ({type(e).__name__}: "
                             f"{str(e).splitlines()[0]}): {PDF_HINT}") from None  # fmt: skip
    document = weasyprint.HTML(string=page).render()
    pages = len(document.pages)
    start = next((i for i, p in enumerate(document.pages) if APPENDIX_ANCHOR in p.anchors),
                 pages)  # fmt: skip
    return document.write_pdf(), pages, start
