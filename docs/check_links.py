"""Checks every internal link of the built site: each relative `href` or
`src` of every page must name a file of the site, and each `#fragment` an
`id` in that file. External links are not followed (the site is checked
offline); the Rust API copied under `rust/` is checked by `cargo doc -D
warnings` and is only linked to.

    python docs/check_links.py docs/_build/html
"""

from __future__ import annotations

import sys
from html.parser import HTMLParser
from pathlib import Path
from urllib.parse import unquote, urlsplit


class Page(HTMLParser):
    """The ids and the link targets of one HTML page."""

    def __init__(self) -> None:
        super().__init__()
        self.ids: set[str] = set()
        self.links: list[str] = []

    def handle_starttag(self, tag: str, attrs: list[tuple[str, str | None]]) -> None:
        for name, value in attrs:
            if name in ("id", "name") and value:
                self.ids.add(value)
            if value and ((name == "href" and tag in ("a", "link")) or (name == "src" and tag in ("img", "script"))):
                self.links.append(value)


def parse(path: Path) -> Page:
    page = Page()
    page.feed(path.read_text(errors="replace"))
    return page


def broken_links(site: Path) -> list[str]:
    """Every internal link of the site that names no file or no id."""
    pages = {p: parse(p) for p in site.rglob("*.html") if "rust" not in p.relative_to(site).parts[:1]}
    broken = []
    for path, page in pages.items():
        for link in page.links:
            url = urlsplit(link)
            if url.scheme or link.startswith("//"):
                continue
            target = (path.parent / unquote(url.path)).resolve() if url.path else path
            if target.is_dir():
                target = target / "index.html"
            where = f"{path.relative_to(site)}: {link}"
            if not target.is_file():
                broken.append(f"{where} (no such file)")
            elif url.fragment and target.suffix == ".html" and "rust" not in target.relative_to(site.resolve()).parts[:1]:
                ids = pages[target].ids if target in pages else parse(target).ids
                if unquote(url.fragment) not in ids:
                    broken.append(f"{where} (no id {url.fragment!r})")
    return broken


def main() -> int:
    site = Path(sys.argv[1]).resolve()
    broken = broken_links(site)
    for line in broken:
        print(f"broken link: {line}")
    count = sum(1 for _ in site.rglob("*.html"))
    print(f"internal links of {count} pages checked: {len(broken)} broken")
    return 1 if broken else 0


if __name__ == "__main__":
    sys.exit(main())
