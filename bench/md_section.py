"""Replace one marked section of a Markdown file, leaving everyone else's text alone.

A section is the text between `<!-- begin NAME -->` and `<!-- end NAME -->`; if the
markers are absent the section is appended at the end of the file.
"""

from pathlib import Path


def replace_section(path, name, body):
    path = Path(path)
    begin, end = f"<!-- begin {name} -->", f"<!-- end {name} -->"
    block = f"{begin}\n{body.rstrip()}\n{end}\n"
    text = path.read_text() if path.exists() else "# Benchmarks\n\n"
    if begin in text and end in text:
        head, rest = text.split(begin, 1)
        _, tail = rest.split(end, 1)
        text = head + block + tail.lstrip("\n")
    else:
        text = text.rstrip("\n") + "\n\n" + block
    path.write_text(text)
