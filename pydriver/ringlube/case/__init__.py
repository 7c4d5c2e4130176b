"""A ringlube case: a namelist deck you can read, change, validate and hand to the kernel.

:class:`Case` (:mod:`ringlube.case.case`) and the pieces it is made of: the deck's items as
the kernel's scanner reads them (:mod:`ringlube.case.items`), namelist values as text
(:mod:`ringlube.case.text`), the case handed to the kernel (:mod:`ringlube.case.kernel`) and
where each input comes from (:mod:`ringlube.case.origins`).
"""

from .case import GROUPS, Case

__all__ = ["Case", "GROUPS"]
