"""docs/results.md's sections: the report is cut before each '## ' heading, so that sections written
by hand survive a regeneration."""

import re


def sections(text):
    """[(heading line or None, text)]: text cut before each line starting with '## '."""
    parts = re.split(r"(?m)^(?=## )", text)
    return [(part.splitlines()[0] if part.startswith("## ") else None, part) for part in parts]


def keep_hand_sections(old, new):
    """new with the sections of old (its generated part) that this script does not write, each put
    back after the section it followed (e.g. "Speed beside the paper's", written by hand with
    figures from other runs): regenerating must not lose them."""
    new_parts = sections(new)
    written = {h for h, _ in new_parts}
    previous = None
    for heading, part in sections(old):
        if heading is not None and heading not in written:
            at = next((k + 1 for k, (h, _) in enumerate(new_parts) if h == previous), len(new_parts))
            if not part.endswith("\n\n"):
                part = part.rstrip("\n") + "\n\n"
            new_parts.insert(at, (heading, part))
            written.add(heading)
        previous = heading
    return "".join(part for _, part in new_parts)
