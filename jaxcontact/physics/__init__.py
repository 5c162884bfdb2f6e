"""The physics of one asperity (Sec. 2), of interaction between asperities (Sec. 3) and of the
size distribution (Eq. 30), as power laws in the contact area."""
