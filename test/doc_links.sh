#!/usr/bin/env bash
# Every relative Markdown link (and image) in README.md, the other top-level pages, doc/ and
# models/ points to a file or folder that exists, and every #anchor to a heading of its page
# (GitHub's heading slugs). Links inside code are not links. Fails naming each broken link.
# Usage: doc_links.sh SOURCE_DIR
set -euo pipefail
root=${1:?usage: doc_links.sh SOURCE_DIR}
python3 - "$root" <<'PY'
import os, re, sys, glob

root = os.path.abspath(sys.argv[1])
pages = sorted(set(glob.glob(os.path.join(root, "*.md")) +
                   glob.glob(os.path.join(root, "doc", "**", "*.md"), recursive=True) +
                   glob.glob(os.path.join(root, "models", "*.md"))))
LINK = re.compile(r"!?\[(?:[^\]\[]|\[[^\]]*\])*\]\(\s*<?([^)\s>]+)>?(?:\s+\"[^\"]*\")?\s*\)")

def prose(text):
    """The page without fenced code blocks and inline code."""
    text = re.sub(r"^(```|~~~).*?^\1[^\n]*$", "", text, flags=re.S | re.M)
    return re.sub(r"`[^`\n]*`", "", text)

def anchors(path):
    """GitHub's anchors of a page's headings."""
    found, seen = set(), {}
    for line in prose(open(path, encoding="utf-8").read()).splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*#*\s*$", line)
        if not m:
            continue
        title = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", m.group(1))
        slug = re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-")
        n = seen.get(slug, 0)
        seen[slug] = n + 1
        found.add(slug if n == 0 else f"{slug}-{n}")
    # Headings written with backticks lose them in the slug too.
    for line in open(path, encoding="utf-8").read().splitlines():
        m = re.match(r"^#{1,6}\s+(.*?)\s*$", line)
        if m and "`" in m.group(1):
            title = re.sub(r"!?\[([^\]]*)\]\([^)]*\)", r"\1", m.group(1)).replace("`", "")
            found.add(re.sub(r"[^\w\- ]", "", title.lower()).replace(" ", "-"))
    return found

broken, checked = [], 0
for page in pages:
    for target in LINK.findall(prose(open(page, encoding="utf-8").read())):
        if re.match(r"^[a-zA-Z][a-zA-Z0-9+.-]*:", target):
            continue  # http:, https:, mailto:
        checked += 1
        path, _, anchor = target.partition("#")
        resolved = os.path.normpath(os.path.join(os.path.dirname(page), path)) if path else page
        where = os.path.relpath(page, root)
        if not os.path.exists(resolved):
            broken.append(f"{where}: {target}: no such file")
        elif anchor and resolved.endswith(".md") and anchor not in anchors(resolved):
            broken.append(f"{where}: {target}: no heading with that anchor")
for line in broken:
    print("doc_links:", line)
print(f"doc_links: {checked} relative links in {len(pages)} pages, {len(broken)} broken")
sys.exit(1 if broken else 0)
PY
