"""Studies of the library, apart from it (the library never imports them): the paper's figures,
speed against a plain scipy implementation, accuracy against an mpmath reference."""
