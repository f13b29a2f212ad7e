#!/usr/bin/env python3
"""Checks for tests/browser/pages_test.sh on what headless Chromium made of a result page.

page_check.py dom PAGE DOM MIN_SVGS TEXT...
    DOM is the page as Chromium parsed it (--dump-dom). It must hold a table, at least MIN_SVGS
    <svg> elements and each TEXT; no element may load anything (no src, no <script>, <link>,
    <img>, <iframe>, <object>, <embed>), and every link must be relative and name a file that
    exists beside PAGE.
page_check.py png SHOT WIDTH HEIGHT COLOURS...
    SHOT is a screenshot (--screenshot) of WIDTH x HEIGHT pixels. It must decode, and show more
    than a blank page: many colours, among them each COLOURS argument, a colour RRGGBB or
    alternatives RRGGBB|RRGGBB of which one must show (a page's green or red of a verdict, which
    only its style sheet paints; a map's blue and vermillion cells).
page_check.py svg FILE COLOURS...
    FILE is a standalone SVG document (a sweep's map.svg): it must parse as XML, its root must be
    an <svg> of the SVG namespace whose width and height are positive numbers (the natural size
    an <img> of it would take), and it must fill something with each colour RRGGBB of COLOURS.
Prints what failed and exits 1, or exits 0.
"""
import html.parser
import os
import struct
import sys
import urllib.parse
import xml.etree.ElementTree
import zlib

LOADING_TAGS = {"script", "link", "img", "iframe", "object", "embed", "audio", "video", "source"}


class Elements(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.tags = {}
        self.hrefs = []
        self.loads = []

    def handle_starttag(self, tag, attrs):
        self.tags[tag] = self.tags.get(tag, 0) + 1
        if tag in LOADING_TAGS:
            self.loads.append("<%s>" % tag)
        for name, value in attrs:
            if name == "src" or name == "srcset":
                self.loads.append("%s=%r on <%s>" % (name, value, tag))
            if name == "href" and tag == "a":
                self.hrefs.append(value or "")


def check_dom(page, dom_file, min_svgs, texts):
    dom = open(dom_file, encoding="utf-8").read()
    elements = Elements()
    elements.feed(dom)
    problems = []
    if elements.tags.get("table", 0) == 0:
        problems.append("no <table>")
    if elements.tags.get("svg", 0) < min_svgs:
        problems.append("%d <svg>, at least %d expected" % (elements.tags.get("svg", 0), min_svgs))
    problems += ["loads something: " + load for load in elements.loads]
    folder = os.path.dirname(os.path.abspath(page))
    for href in elements.hrefs:
        parsed = urllib.parse.urlparse(href)
        if parsed.scheme or parsed.netloc or href.startswith("/"):
            problems.append("a link that is not relative: " + href)
        elif not os.path.isfile(os.path.join(folder, urllib.parse.unquote(parsed.path))):
            problems.append("a link to a file that is not there: " + href)
    problems += ["missing text: " + text for text in texts if text not in dom]
    if not elements.hrefs:
        problems.append("no link to the neighbouring files")
    return problems


def png_pixels(path):
    """(width, height, rows of (r, g, b) tuples) of an 8-bit RGB or RGBA PNG."""
    data = open(path, "rb").read()
    if data[:8] != b"\x89PNG\r\n\x1a\n":
        raise ValueError("not a PNG")
    at, idat, header = 8, b"", None
    while at < len(data):
        length, kind = struct.unpack(">I4s", data[at:at + 8])
        body = data[at + 8:at + 8 + length]
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat += body
        at += 12 + length
    width, height, depth, colour, _, _, interlace = header
    if depth != 8 or colour not in (2, 6) or interlace != 0:
        raise ValueError("depth %d colour type %d interlace %d: not read here" %
                         (depth, colour, interlace))
    channels = 3 if colour == 2 else 4
    raw = zlib.decompress(idat)
    stride = width * channels
    rows, previous = [], bytearray(stride)
    for y in range(height):
        kind = raw[y * (stride + 1)]
        line = bytearray(raw[y * (stride + 1) + 1:(y + 1) * (stride + 1)])
        for i in range(stride):
            left = line[i - channels] if i >= channels else 0
            up = previous[i]
            upper_left = previous[i - channels] if i >= channels else 0
            if kind == 1:
                line[i] = (line[i] + left) & 0xFF
            elif kind == 2:
                line[i] = (line[i] + up) & 0xFF
            elif kind == 3:
                line[i] = (line[i] + (left + up) // 2) & 0xFF
            elif kind == 4:
                p = left + up - upper_left
                pa, pb, pc = abs(p - left), abs(p - up), abs(p - upper_left)
                predictor = left if pa <= pb and pa <= pc else up if pb <= pc else upper_left
                line[i] = (line[i] + predictor) & 0xFF
        rows.append([tuple(line[x * channels:x * channels + 3]) for x in range(width)])
        previous = line
    return width, height, rows


def rgb(hex_colour):
    return tuple(int(hex_colour[i:i + 2], 16) for i in (0, 2, 4))


def check_png(path, width, height, wanted):
    try:
        got_width, got_height, rows = png_pixels(path)
    except (OSError, ValueError, zlib.error, struct.error, TypeError) as error:
        return ["cannot read %s: %s" % (path, error)]
    problems = []
    if (got_width, got_height) != (width, height):
        problems.append("%dx%d pixels, %dx%d expected" % (got_width, got_height, width, height))
    colours = set()
    for row in rows:
        colours.update(row)
    if len(colours) < 16:
        problems.append("%d colours: a blank page" % len(colours))
    for alternatives in wanted:
        if not colours & {rgb(colour) for colour in alternatives.split("|")}:
            problems.append("no pixel of #%s: the page's colours did not apply" %
                            alternatives.replace("|", " or #"))
    return problems


def check_svg(path, wanted):
    try:
        root = xml.etree.ElementTree.parse(path).getroot()
    except (OSError, xml.etree.ElementTree.ParseError) as error:
        return ["cannot read %s as XML: %s" % (path, error)]
    if root.tag != "{http://www.w3.org/2000/svg}svg":
        return ["the root element is %s, not an SVG document's <svg>" % root.tag]
    problems = []
    for side in ("width", "height"):
        try:
            size = float(root.get(side, ""))
        except ValueError:
            size = 0
        if not size > 0:
            problems.append("%s %r: a browser would show it with no size" % (side, root.get(side)))
    fills = {element.get("fill", "").upper() for element in root.iter()}
    problems += ["nothing filled #%s" % colour for colour in wanted if "#" + colour not in fills]
    return problems


def main(args):
    if len(args) >= 4 and args[0] == "dom":
        problems = check_dom(args[1], args[2], int(args[3]), args[4:])
    elif len(args) >= 5 and args[0] == "png":
        problems = check_png(args[1], int(args[2]), int(args[3]), args[4:])
    elif len(args) >= 2 and args[0] == "svg":
        problems = check_svg(args[1], args[2:])
    else:
        print(__doc__)
        return 2
    for problem in problems:
        print("FAIL: %s: %s" % (args[1], problem))
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
