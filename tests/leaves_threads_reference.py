"""Induced masks of main before the threaded analysis (commit 87217cb), for tests/test_leaves_threads.py.

Each entry: (kind, layer, exemplar) -> (shape, zlib-compressed np.packbits of the mask, base64). Made by
analyze() on leaf_family(3, size, kind, rng=seed) with simulate_scribbles as in the test.
The spots entries of exemplars 1-2 were made again at leaves73 (issue 22: scattered marks are not
snapped and are read where the veins were removed by their mask alone); their IoU with the true
spots rose (lobed 0.78 / 0.57 -> 0.89 / 0.82, elliptic 0.52 / 0.77 -> 0.83 / 0.93), the veins' are unchanged.
Made again at leaves75 (a scattered layer's edges by its pixels' colour, marks the veins took given back
by shape): lobed 0.893 / 0.822 -> 0.898 / 0.772 (exemplar 2's 63-px spots gained a 7-px rim of their
soft edge), elliptic 0.826 / 0.932 -> 0.835 / 0.950; veins kept as main's (elliptic exemplar 1 now has
1 px less, IoU 0.999).
Spots made again at leaves85 (a mark's edge by the exemplar's own marks' colour and the blade's colour
round it, not nearer a layer above's colour): IoU with the true spots lobed 0.907 / 0.898 / 0.772 ->
0.907 / 0.920 / 0.897, elliptic 0.905 / 0.0507 / 0.950 -> 0.905 / 0.0504 / 0.959 (exemplar 1's
registration fails: its spots are elsewhere either way); veins kept.
Elliptic entries of exemplar 1 (veins, spots) and exemplar 2 (veins) made again at leaves87: the analysis
had turned exemplar 1 over (its outline's mirror image fitted better under rigid maps, chamfer ratio 0.58);
now registered both ways, it stays as it faces (registered blade IoU as good; true keypoint error 0.9 px
against 24 px turned over). The "0.05" above was its turned-over masks against the unturned truth; with
the truth turned likewise it was veins 0.734, spots 0.882. Now, against its own truth: exemplar 1 veins
0.737, spots 0.882 (same pixels, unturned); exemplar 2 veins 0.788 -> 0.753 (the layer's shared delta,
IoU 0.954 with the old entry); every other entry unchanged.
Made again at leaves94 (issue 22: the training leaf's thin vein layer grows along its fainter
unscribbled lines): every entry from this branch's analysis. Vein IoU with the true veins, exemplars
0 / 1 / 2: lobed 0.778 / 0.684 / 0.384 -> 0.845 / 0.748 / 0.522, elliptic 0.691 / 0.737 / 0.753 ->
0.843 / 0.756 / 0.800; spots unchanged but elliptic exemplar 2 (0.949 -> 0.945).
"""


REFERENCE = {
    ('lobed', 'veins', 0): ((170, 172),
        ('eNrtVrFu1EAQnbm11g5ZnY1oNsLKmQZKlgaliBIXlPkIRyloImGoLhV7XESaFCn5DOgo93RSqog6pSWokRHNRQo6xifF9tpbQEGB'
         'dHPSyXp6O56defNkgHWs478M4UTNH1MzF3XgpCZ/QZ07QHYbOdD9mXbVKl1p3dTA2QFXscJZrEn7mBbccTw1WR+9EgMH1eikj74Q'
         'rA+Gy2nZR0+DB31Qplr1QDwNsE+NUm11e3Ud5nWoGVA+1aXyIWXl2zY1PaGOqsOFRRVYCqJKm2o4JYZHWtrqM1UNK2pDL2RVAVZU'
         'XtN9Rghdgf7iZuQ7CeUQCBLCxb06waVHYjejGw1fdVHfwIwDoi4X9L7dmjpmPyZaR9UIzmpwQ7Nyp+oK0szuwEMOnGHVFQnjOqlS'
         'MM5kddz49fnnaMQ3rMbCsTy4G4kZ4tRIRnNVz8503azPMsblEpDxoJ6j2ZqDoaKEkmZaN4sNM46Q4BSuZU1N813IowF8THx830wL'
         'TYg6GQ4gV7U8U6qArlpkWdjaewEqQnjMBH7Auq+o6fn+G5BGmWa4isjoF3DNvUazDHQGEQefet4IkXrCVlKSMGgpQ+/mpDqcBtAs'
         'TSrZ94oqTnRrv1Af6Uqgx2XbuBR5QJQdsMu2cfkzPWP+0ijFGi/AL4pHagwMIW+dP4Ln3KO3Ba3znGVospRSWl4SQzz0aGw8by/W'
         'RGdFCnv0a4WS/KFHYsC2wdCsfsr09Rys9czUViFGi8SykiHDc5iF3PboPM8zAYWJLcM8DxkYCcyyvXBipCAot3Yul2R5x2BbEQ2W'
         'i7jrWbTdav6u70QszqHvb1tXLs/8pbHrxQz8MunZ0xPY5qzoUg0z5mU3QYTLK6/r+zO8CXXXy73o9uJtz/YP9za8/W5SPoILvehS'
         'n+rNIBgPulXBp8mktK7gYQGbIEeXtsFRwgQnoXUvvqep/ZGy1AKvgkrvvLGRlYopAYkiw3YCLENY9d+Sy7gLrKpa7ZJrLp7zcyBd'
         'fyetYx3/On4DnoWyJw==',)
    ),
    ('lobed', 'veins', 1): ((170, 172),
        ('eNrtVjGL3EYU/mZHHm0xrARpJrCcBGkDkXGRNTlu5c4/Q2CwS2+XA5vzLIuNi/wAFyG/wWWqeNYLrgyX0oXBOgyuXOjAxRbHnd8c'
         '9mqepCpdYKeY4uPTvO99894bAfu1X/v1X9doEK2GwGdD4MR1gMJvjzug8JvccNAZv5uCgRr+QLG0DK2V31MTYtHltUwpGPWkkNcq'
         'GDWRmAHxhlNLE1uI03zGpdq39HkiuVatq+vDOxmsvI5HHFQ+lt40HM197MeKmxJTuhDcQSMbjxguanmGE6+Nizo0KkfOqTgV9jWE'
         '1AxMnNYFec1jLeA2kLc4FTYyqb7ZrC2/l2q5XMWfeTCn6Mz84cZ2akD8M9JHL3kKK2QO7knH1yL+A1p1ymX9tHaiLju+zk40sqhD'
         'nf9VOfGyQ41PVyiKTlqo60Ku0JF6l1hqkbTAbeebgm77Prat+CvfFCRT1ONd/SH5OcfYF3wQyaH4RPckp0DrtVYj5coUvzpM2xJy'
         'VXVMX8o6Eh9tS1WJtf7+6x/qluru2AN//yM5nbQ1qSFI4yEderYL1jiHH0scuNef4r93hrwd4+YIcaR/qrPdqdnSygbSlW+maGPN'
         'DdUlisjkbhoYYClRi3vPjGwdTC8gSemoEXaxAyVpyqWXVQTDpUjqEZ0QQ7JWeeM30bCBUXk7K3luVdBDEm5CPp8YbIIaLsaYks/C'
         '6klApWkz0ymxw7tOU5JENb1+x7sduDCYUgFkQQ/SIee4UR9e+/udulV40OC+WoR9SH2hshJVZcOWdVNTHkFGYFUgRYQj+B4MC6Yo'
         'SmwldQGCmSHUBOLf2xblL1eB3+WWptg7qORLe8CTKLHI5sDDwK64sc+BVw2yszDb50ZhfIkPdRrOhrWtsbq6NIJNjBca44RSZR2f'
         'XTh/XUbUrAkvgN+ImvGZs0VEM6cztOJXoHdgueVtmFhDcebd16Uz3NnD0VkHGKDK8/EA9feFG3jI5lEfFGs38BQeQ/VBuoQ+Vb4f'
         'emCPHYq+/glk/3sKn/bQbYy+L5nN0fNF/unneRdd8Ar8lv+EFeu3/B1N1p6Fs6EfAbn/l9qv/+36CsfBxyw=',)
    ),
    ('lobed', 'veins', 2): ((170, 172),
        ('eNrtVr9rFEEUfrOzmV3C5G5BhZWsyWGhUQJuIWEtTFZsLQI2kmokjYXK2tgoMiYQG/8AGyF/gqWVbCwSy5SWi2kFD1J4he45+0Od'
         't/tAS4XMwd7x3Tfvvfnem/cW4GSdrH9rRSQ6pkD+Z2tMU2BCUa///JHa1LzFhrYh2XwNzMda7T4FIwt0eL3R6Tgr6mcnjtONy10E'
         'isbxpib0kBKBrROtEJrVzwC78logR7pMGrl8+wCjSzth/ad9BEfM3a2pCzctVMGkoa5YBgSIRsT4mW0VsiZ29saOn7cBceu0aZAM'
         'GzS0Y2XPy2qLRhleD+/H5msZUWehrCqFoWJg+VAntU0flVRRkZgR0UYf1/ZiTBUKtKRq0sl7qAnqqF+GBu9XewBzVXZtGy4MB6xw'
         'tBY2UbHNUQIbISo3F8KPXDsb+G7EF6QJYS9DsvDXWnEIBviOLBonqkplbEc6gtT49rFVabypKlJUbxpi4eiIvezqEsdMSyyNXOIM'
         'LsMEU0c6UPyO1y1YGMJtFWN0TcNncW4HYT77AHNjfRWX9hZo9uJWx1UU+xDOpxzfrQNImb4H2NWsES9xOi2HlXBm22QsQw3jyoSr'
         'TKAr/0TPCJ1UylpRzX8plM+0qnS09n8y0YTSEO2ouAmc7eV+r6xMFsJeWd04LnDHdGEdPF6imAaQG7/ZIMPdIgLFOWD1OdMOBEsd'
         'SVYjKBjTHUmmuYQgrIKy+qg3Heeivqt2x3z0/R2YjEZgV5BI1saCu+b8tmHTZrxdNTL3bel3KxMmnoMdWe9m9g10j4v3otf11Fep'
         'VN4ZGw5M97nfavlr5fKbuuZAyDqXs+SHQW+k8MkaZ8XZsoMeFRdn2LTAqFNGb/ujxzvENKfWY/EQs1ZrfdNOtp9Wz5WuwXHToIi1'
         'T4FhTI3XbYqqKKqk5izTIUGNKSrPKVcPKVCO/nLMszEV6YMtAvQkKdUyBXrUGwXEJJV8JSkA+rosEGdwq9nYoxbnoTOdqlSLAOwu'
         '0o6SnKByKilwinx5yih0kRKAvyINpBTqkrLkJ6++/+v6AVndnUY=',)
    ),
    ('lobed', 'spots', 0): ((170, 172),
        ('eNrtlM0JwjAYhhMK9iLt1UNoVnAAaVdxkKIdxGHqAuII3nq0NyNIY3L9fAYo8r2QQF4evr+EGKNSqVQq1X/pQWZ1FEY+dzdhtmmV'
         'bxGgyOfYCrQbjakniS5p62eB+kxthGkXKtNj8f16hz2SuSXTInogs0T0Z2D7PDA57GJIqaJEQ1o7OVufUOOEWQeo1cYBCnIB26Ti'
         'Hfb5JLT6EDrho6b8V3pC/k4oZmoavBKKak+Evqgrj0Fncs+Uqrzox6ZSrUtf6kssmA==',)
    ),
    ('lobed', 'spots', 1): ((170, 172),
        ('eNpjYBgFo2AUDBvAgU2Q8QA2URlsgsxYlcphtYsEpQVY7RqNrlEwCkbBIAAN2AR5HmArTN8Rb6o9NkH2H9hE/2MrTfn/YFNaj81Z'
         '7NiVYjOVHZt+hgqsRTTWcDEYTS+jYBSMAhgAALumDy4=',)
    ),
    ('lobed', 'spots', 2): ((170, 172),
        ('eNpjYBgFo2AUjIJRMAqGFWDBKuqATZAVmyDzH2yi9QewKf2BTSl7AzbRGqxKsZnKYINNkPHAaNQOdfACmyAb1uTihzVpPyA6aY+C'
         'UTAKRgFtAQAnBgkq',)
    ),
    ('elliptic', 'veins', 0): ((204, 198),
        ('eNrtVr+LFDEUfpmMyRRhJ4dNYNfbEdsDcwoyyLKMIP4d8bS02PIEYTO3y10jnKV29yfcn5DzBK3UP8BiDntZu0W2MFfPl0IQBNlX'
         '5s3ky3vf934QbW1rW/vn5hLnbJX6I+kI+FjwxPdmkHA8vYvPd05eY8cTkQii1tghz5rEmy5Sb1IJiKXFVwlqcUKKjHnosCZLJPYQ'
         'g3M2szCIXDUQu9GWwSDOXYAplPKIDIR4aBSUTqXcTRie36EX6Dyjx9TBPJUWK8feW9Y4T4MdCM2p3oPRLcl1mAmGoYPbTCrIhN9/'
         'h7Dzkr5BbP2KB4jd2DEWmnfPCelAsNYQ0kFxpCyU2kTZABXVaY8agmF0QCghLudvoT7a9bBB/SAT1UdCZa/IjzQSVNSAvQOpyMmv'
         'UZ7IZOwMUUHu6wiVhW7aiyvU1dyCl+0CQCyU+k4jEJ7SU4XiLowLul9hGV/tHxMgL17yUhMgL6Yjb6iE6RgS/egrszJUk+yTJCPT'
         'rqgR2555VEhul2TYQ8pUMYTQZ09YHWsSRFGSy2gGJFjxN0YCCcow9G7G+1zcog+sDEMD2q8pf5LsYw+pmnBE3iFdxUBATQYWOeqL'
         'tliseBwvs55jKkMeEPTMXHM0B5K97dcMDDdBn8vuuO5HV7DuPi8BRw8kqRyVRcx2NQ+IvBk7vUR9WXayU2AiKf1+QtMCCccGcrYP'
         '4mRMIH0BmVUxNL4CDVu7HKlc0DPSYANxSnzSUZ99BLvfPToJqJvyVqzRrAgqn4ORPoiNaHwFUm4EnazQ9LRKbKgAVzm7S6i4Yw2t'
         'rvsUeO1Rk1egx0tuvPGA1lw0dLCLBveYtaeoC9qal2s4dlz5Cw1Puiw3QAU0YKcbQkNSZZO4BqA33cALEdWj1NZqUzuoJzw+lzTf'
         'wN3Ajtd4f+sSEKmtlcapzTgc4vOMEmHoP1yxKUv9UKQcTWrv/2s3bW1rW/vf7Dd7EKED',)
    ),
    ('elliptic', 'veins', 1): ((204, 198),
        ('eNrtVzFv00AYfeezbFO5cZi4SsENU1cXpMgSJmTid1yEBAuDJZYMqL00qF0K6k9hZLy0iKkSa5E6XNQVIY9BIISZ/W5AQoghN+bl'
         'vu/eu/d99xnYrM3arP9ziZ8eILAeQPpCpT6gX/DfzYTnCETMN6jwgAOTnSvPWTXPnQijKaAjYSjwQ0kKSKtzuqENdMlZROC5C+XJ'
         'rQuurbRHnF4mcx7pWdLjNkiHAy7twLziwP2gT9mJL4qTUA2nbZcLFPTyghTMIRGSIqAOlKs1TV7cvnQ0uZb7C6qH3TZU8xgjfnsH'
         'RSMcY3G6cBkDUGWW31790PDbczaiJMTcKEpCRigrpmyuwqJkyr6Y9TXhtyXvuuWcKYvHQcCU0pipZMiuW7g183ls3lzMQrJhJG+U'
         'I5HE6zidzolBQoUHUWzpaa/VPvfBbHhEO0tWR9wglRszYPtsalgzMnvzExZpJE6iVBGfr6NcwRGlLAY6XnVP2/anR6YMuk6INfLE'
         'ht0UWYJqhC1iTY26AfHUd2BpWFFWkClYUdZIa7BO4fByAuID0YjPJqKSi/M2HAMiCP4uKCTk/0ZYjbKL9CCWRhLeNeR5+3O3XA12'
         'PhnbFaR9wG7WIXkrMwhpa5KiN4SUINIOjpAOQASp+uhfsc55bfBkuOxGkjnEe7wlPbsK40YQaYfjYmBpJY3tPZOwLrXbavKUAfni'
         't0VYS72EqinQYPWxK1QfykakdY4nkyn2ScFkUoSCtfNeEqqEtfNMK23ZEJKZ6TFKBuC4EJbuuGXomxubCpy2cXzUuLNgJdk6/OKU'
         'pi6EPOuxYl1BOp2RwvgAeYIZq0lEZcyK1YY7tqSjye5XyQ4lTOwq3lElZdECqWdocYXjs0nznI9k+PYuATXt4YKG2rUVHznjZo8P'
         'r3K99ozBh+aPB2cfoH3TvC9F5IukfMDQB5i/9l1Q+ICJj97me22zNusfrV/dUK/z',)
    ),
    ('elliptic', 'veins', 2): ((204, 198),
        ('eNrtV7FuFDEQfY5P3pNY9lI60pI9wg9sRJFFnJKTkPgOozQpKJaKQ4pgjki5JgLKFEj8AiUVOBRUfALFUoOilWiuiAiGEj8XIOjO'
         '0jWe83g8782bWWC1Vmu1/mqtJ/bracJwJnxfm8SB3I65YS/l6jLhaiu3dF8tJwlPbpkI6ohvD5Bzg0WdyBM8N3jN95UkrjBuL5En'
         'XAypp5draGnG6yE6HtRYfeRBiXYU1TVk1FMxTIBxMG5oRrSVhxQibOE7DQkHNFgN3eUlSyCuScu4NsRdLULBsyXnDRxPoKgFZ39t'
         'GmrIZENokeU4BEXJ6g6MO67OoD6xRDkbUkJiUt4x9NQgmwsIeqbfWVyymEbqWVUyHlhTOrCHt7glivHgPXZRMLhPMaNs1h7ddaFw'
         'Kzmh9IfhZLawGTTx1cPZLGclqcTvkqi2vTHqFfF0JLbGhISU+X1BHFWDXL1kMTmUWQfCTo9mkxEn+OhbRhwzNZ+FgTSS7Q8QAtJE'
         'H50apsFtiMkyIfRdJg88CWoewP46iu8IZLKqv/k61pXwdB2yFSlzGeBm1GlqmFAWcVTOYVaMYxKquc+6PvakC/1CLSQmYbGsxMx+'
         'CtJvq5Lz8CMto9G/qjuGuy3KEBABqSsnBcaWFPd6Y+E9UUFMPeu5QSS+wBCQChSHuELAm6Bt6yZ+nloG9nsfP69otdYltqMTY2fy'
         'wNpz8j5bV1B9/D4PfxGqhpS9HllF+F9J3tZ5F88x+7IjvoppoDOEKWAWczavgrYQfpzg8VUhpad7vXmDlV6G4aEwpS2g37Krg/Oy'
         'oUrUBNoOdlmrujeXDdIO1TdjhvfX47ZnltbWHYRol3PnTIPV2XzeszlHyyCwirZi2zKNCrm4I2CkLVSjjpmWF5kYIrS5KycYkRsq'
         'hDGjoSJ/G7TzNKEkcz7C9VPa7VucHfPxQOuWTj9dnvHJq6vbER28/ELoDKeezugBq57LjBlm+k1Gp+BW8wNoDD+A1vIDaPYTc/aj'
         'dz03PLnsEobUB0ni/9CpA3nKUKcM/p9dMU4ZEnnCWurAMGVwSH1HJAyp7zDYP75i9Xm8Wv9x/QCkx8M/',)
    ),
    ('elliptic', 'spots', 0): ((204, 198),
        ('eNpjYBgFo2AUjIJRMApGwSgY9uABDnHmAzgk+C1wSNjjMIrxPy6TfuCQMD6GQ+JdBQ6Jybi8Yd+Aw1F/sIvL83/ALlEhPwObsAFj'
         'T00CNi8cYDB8gs3eZwxsh7E5lv0GgwQ/NsfKA7EdNpP+AQlsjmUHeo0Rq0k/SIw5BhuSU03DaI4aBaNgFIyCUTAKRgF9AAAkiRxI',)
    ),
    ('elliptic', 'spots', 1): ((204, 198),
        ('eNrtlD0OQEAQRrGFDq3GGZSO4xSiwgEcyjGUKrWoSdDPK4go5HvJNvMy2flJxvOEEEL8iZ5EAvGAEjISe2fHw1XjF1/gk4hI5CS6'
         '96oqqVr6IxxAtJDhNkhwC4mJxCd7ogbj20enpiHO1GBhBNOrKGsk1VWU9cV4vsY6m+e2XX1n20IIIYQQDzkAc3wRKw==',)
    ),
    ('elliptic', 'spots', 2): ((204, 198),
        ('eNrtlLEJhUAQRO80MPsaKgg2YfAD8azEOgwELcNyzGzDzNTQ4AduATPpB3EeXLLDMsfs3jknhBBCiPcQMaFciDDsuO4PIiRhxULx'
         'IxbpSYSJ3XZgwv78EeVMsJQ8ija2YgXjs44RNdjoPEoqDXaQRX6ZxYyGbcUeebd2vmht2BL48y/pXsyeLK2rOyJs7Ik1zIJ5f9hl'
         'M31YQgghhLgBZfkaZw==',)
    ),
}
