"""Write the report's document as one self-contained HTML page and as a PDF.

The page embeds everything it shows: figures as ``data:image/png`` URIs, each figure's data as
a ``data:text/csv`` download link, and the stylesheet inline, so it references no file or
address outside itself (the same CSVs are also written beside it). The PDF is the same HTML
laid out by WeasyPrint with the stylesheet's print rules; WeasyPrint needs the Pango system
library, and without it the HTML is still written and :func:`pdf` says what to install.
"""

from __future__ import annotations

import base64

from usvtool.report.document import Section
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


def html(title: str, subtitle: str, sections: list[Section]) -> str:
    """The report page."""
    return render("report.html.j2", title=title, subtitle=subtitle, sections=sections,
                  png_uri=png_uri, csv_uri=csv_uri)  # fmt: skip


def pdf(page: str) -> tuple[bytes, int]:
    """The page as PDF bytes and its number of pages; :class:`PdfUnavailable` without
    WeasyPrint."""
    try:
        import weasyprint
    except (ImportError, OSError) as e:  # OSError: Pango missing (cffi cannot load it)
        raise PdfUnavailable(f"report.pdf not written ({type(e).__name__}: "
                             f"{str(e).splitlines()[0]}): {PDF_HINT}") from None  # fmt: skip
    document = weasyprint.HTML(string=page).render()
    return document.write_pdf(), len(document.pages)
