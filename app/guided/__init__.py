"""Guided sessions: a protocol object (``six``, ``free``, ``cube24``; ``compass`` and ``noise`` for ``trical
capture``) run on the still poses or turns a page or a board captures — what it asks for next, how it checks
a capture, when it may be solved and how it solves — with the capture rules the pages and the terminal share.
"""
