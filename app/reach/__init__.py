"""Reaching the server from a phone: the address another machine opens, the self-signed HTTPS certificate
that gives a phone's page its motion sensors, and the QR code of that address."""
