"""A generated book that exercises every entry of the function table (sheetkin/xlsx/table.py)
with ordinary, boundary and error arguments: numbers, text numbers, booleans, empty cells,
errors, ranges of mixed types, negative and huge numbers. tests/xlsx/test_function_table.py
recalculates it in LibreOffice and Gnumeric and compares every cell with sheetkin's value.

Sheet D holds the data the formulas read; sheet F one formula per row (column A the
function's name, column B the formula). CASES names the formulas per function; EXCEL_DIFFERS
the cells where LibreOffice is documented to differ from Excel (sheetkin follows Excel).
"""
from __future__ import annotations

import re
from pathlib import Path

import openpyxl
from openpyxl.worksheet.formula import ArrayFormula

# sheet D: what the formulas read
DATA = {
    # A: numbers, negative and huge
    "A1": 1, "A2": 2.5, "A3": -3, "A4": 0, "A5": 1e300, "A6": 4, "A7": 7, "A8": 10,
    # B: a mixed range: number, text number, boolean, empty (B4), text, negative, error, number
    "B1": 1, "B2": "2", "B3": True, "B5": "x", "B6": -1.5, "B7": "=1/0", "B8": 3,
    # C: text
    "C1": "apple", "C2": "Banana", "C3": "cherry", "C4": "  two  spaces  ", "C5": "a*b?c", "C6": "ÄÖü",
    # E:G a table sorted by E (numbers) and F (text)
    "E1": 1, "E2": 2, "E3": 3, "E4": 4, "E5": 5,
    "F1": "a", "F2": "b", "F3": "c", "F4": "d", "F5": "e",
    "G1": 10, "G2": 20, "G3": "thirty", "G4": 40, "G5": 50,
    # H1:I2, J1:K2 matrices; L1:M2 a singular one; N1:P2 not square
    "H1": 2, "I1": 1, "H2": 1, "I2": 3, "J1": 1, "K1": 2, "J2": 3, "K2": 4,
    "L1": 1, "M1": 2, "L2": 2, "M2": 4, "N1": 1, "O1": 2, "P1": 3, "N2": 4, "O2": 5, "P2": 6,
    # Q: numbers only, for the statistics
    "Q1": 3, "Q2": 1, "Q3": 4, "Q4": 1, "Q5": 5, "Q6": 9, "Q7": 2, "Q8": 6,
}

CASES: dict[str, list[str]] = {
    # ------------------------------------------------------------ Math & Trig
    "ABS": ["ABS(-2.5)", "ABS(D!B2)", "ABS(D!B5)"], "ACOS": ["ACOS(0.5)", "ACOS(2)"],
    "ACOSH": ["ACOSH(2)", "ACOSH(0.5)"], "ACOT": ["ACOT(1)", "ACOT(-2)", "ACOT(0)", "_xlfn.ACOT(D!B2)"],
    "ACOTH": ["ACOTH(2)", "ACOTH(-3)", "ACOTH(0.5)"], "ARABIC": ['ARABIC("MCMXCIV")', 'ARABIC("ab")'],
    "ASIN": ["ASIN(0.5)", "ASIN(-1.5)"], "ASINH": ["ASINH(-2)"], "ATAN": ["ATAN(1E10)"],
    "ATAN2": ["ATAN2(1,1)", "ATAN2(-1,0)", "ATAN2(0,0)"], "ATANH": ["ATANH(0.5)", "ATANH(1)"],
    "BASE": ["BASE(255,16)", "BASE(5,2,8)", "BASE(-1,2)"],
    "CEILING": ["CEILING(2.5,1)", "CEILING(-2.5,2)"], "CEILING.MATH": ["CEILING.MATH(-2.5,2,1)"],
    "CEILING.PRECISE": ["CEILING.PRECISE(-2.5,2)"], "COMBIN": ["COMBIN(10,3)", "COMBIN(3,5)"],
    "COMBINA": ["COMBINA(4,3)"], "COS": ["COS(D!A1)", "COS(D!B3)"], "COSH": ["COSH(1)"],
    "COT": ["COT(1)", "COT(0)", "COT(-0.5)"], "COTH": ["COTH(2)", "COTH(0)"],
    "CSC": ["CSC(1)", "CSC(0)"], "CSCH": ["CSCH(1.5)", "CSCH(0)"], "DECIMAL": ['DECIMAL("FF",16)', 'DECIMAL("12",2)'],
    "DEGREES": ["DEGREES(PI())"], "EVEN": ["EVEN(1.5)", "EVEN(-1)", "EVEN(2)"], "EXP": ["EXP(1)", "EXP(1000)"],
    "FACT": ["FACT(5)", "FACT(-1)", "FACT(5.9)"], "FACTDOUBLE": ["FACTDOUBLE(7)", "FACTDOUBLE(6)"],
    "FLOOR": ["FLOOR(2.5,1)", "FLOOR(2.5,-2)"], "FLOOR.MATH": ["FLOOR.MATH(-2.5,2,1)"],
    "FLOOR.PRECISE": ["FLOOR.PRECISE(-2.5,2)"], "GCD": ["GCD(12,18)", "GCD(D!Q1:Q8)", "GCD(-1,2)"],
    "INT": ["INT(-2.5)"], "ISO.CEILING": ["ISO.CEILING(-2.5,2)"], "LCM": ["LCM(4,6)", "LCM(D!E1:E5)"],
    "LN": ["LN(10)", "LN(0)"], "LOG": ["LOG(8,2)", "LOG(100)", "LOG(8,1)", "LOG(-1,2)", "LOG(D!B2,D!E2)"],
    "LOG10": ["LOG10(1000)"],
    "MDETERM": ["MDETERM(D!H1:I2)", "MDETERM(D!L1:M2)", "MDETERM(D!N1:P2)", "MDETERM(D!B1:B2)"],
    "MINVERSE": ["INDEX(MINVERSE(D!H1:I2),1,2)", "INDEX(MINVERSE(D!H1:I2),2,2)",
                 "ISERROR(INDEX(MINVERSE(D!L1:M2),1,1))"],
    "MMULT": ["INDEX(MMULT(D!H1:I2,D!J1:K2),2,1)", "INDEX(MMULT(D!J1:K2,D!H1:I2),1,2)", "SUM(MMULT(D!N1:P2,D!N1:P2))"],
    "MOD": ["MOD(-7,3)", "MOD(7,0)"], "MROUND": ["MROUND(10,3)", "MROUND(-10,-3)", "MROUND(10,-3)"],
    "MULTINOMIAL": ["MULTINOMIAL(2,3,4)"], "MUNIT": ["INDEX(MUNIT(3),2,2)", "SUM(MUNIT(3))"],
    "ODD": ["ODD(1.5)", "ODD(-2)", "ODD(3)"], "PI": ["PI()"], "POWER": ["POWER(2,10)", "POWER(0,-1)"],
    "PRODUCT": ["PRODUCT(D!B1:B6)", "PRODUCT(2,D!B2)"], "QUOTIENT": ["QUOTIENT(-7,2)", "QUOTIENT(1,0)"],
    "RADIANS": ["RADIANS(180)"], "ROMAN": ["ROMAN(1994)", "ROMAN(4000)"],
    "ROUND": ["ROUND(2.345,2)", "ROUND(-2.5,0)"],
    "ROUNDDOWN": ["ROUNDDOWN(3.14159,3)", "ROUNDDOWN(-3.14159,1)", "ROUNDDOWN(31415.92654,-2)", "ROUNDDOWN(D!B2,0)"],
    "ROUNDUP": ["ROUNDUP(3.2,0)", "ROUNDUP(-3.14159,1)", "ROUNDUP(31415.92654,-2)", "ROUNDUP(0.1+0.2,1)"],
    "SEC": ["SEC(1)", "SEC(0)"], "SECH": ["SECH(1)"], "SERIESSUM": ["SERIESSUM(2,0,1,D!E1:E3)"],
    "SIGN": ["SIGN(-0.1)"], "SIN": ["SIN(1)", "SIN(D!B5)"], "SINH": ["SINH(1)"], "SQRT": ["SQRT(2)", "SQRT(-1)"],
    "SQRTPI": ["SQRTPI(2)", "SQRTPI(-1)"], "SUM": ["SUM(D!B1:B6)", "SUM(D!B1:B8)", "SUM(D!B2,1)"],
    "SUMIF": ['SUMIF(D!A1:A8,">2")', 'SUMIF(D!F1:F5,"c",D!E1:E5)', 'SUMIF(D!F1:F5,"<>c",D!E1:E5)',
              'SUMIF(D!E1:E5,3,D!G1:G5)', 'SUMIF(D!C1:C6,"*an*",D!E1:E6)'],
    "SUMIFS": ['SUMIFS(D!E1:E5,D!E1:E5,">1",D!F1:F5,"<e")', 'SUMIFS(D!E1:E5,D!F1:F5,"?")'],
    "SUMPRODUCT": ["SUMPRODUCT(D!E1:E5,D!E1:E5)", "SUMPRODUCT(D!E1:E5,D!G1:G5)"],
    "SUMSQ": ["SUMSQ(D!E1:E5)"], "SUMX2MY2": ["SUMX2MY2(D!E1:E5,D!Q1:Q5)"], "SUMX2PY2": ["SUMX2PY2(D!E1:E5,D!Q1:Q5)"],
    "SUMXMY2": ["SUMXMY2(D!E1:E5,D!Q1:Q5)", "SUMXMY2(D!E1:E5,D!Q1:Q4)"],
    "TAN": ["TAN(1)"], "TANH": ["TANH(0.5)"], "TRUNC": ["TRUNC(-2.567,2)", "TRUNC(D!A2)"],
    # ------------------------------------------------------------ Statistical
    "AVEDEV": ["AVEDEV(D!Q1:Q8)"], "AVERAGE": ["AVERAGE(D!B1:B6)", "AVERAGE(D!C1:C3)"],
    "AVERAGEA": ["AVERAGEA(D!B1:B6)"],
    "AVERAGEIF": ['AVERAGEIF(D!E1:E5,">2")', 'AVERAGEIF(D!E1:E5,">9")', 'AVERAGEIF(D!F1:F5,"b",D!G1:G5)'],
    "AVERAGEIFS": ['AVERAGEIFS(D!G1:G5,D!E1:E5,">=2",D!E1:E5,"<=4")'],
    "COUNT": ["COUNT(D!B1:B8)", "COUNT(1,\"2\",D!B3)"], "COUNTA": ["COUNTA(D!B1:B8)", "COUNTA(D!A1:C8)"],
    "COUNTBLANK": ["COUNTBLANK(D!B1:B8)"],
    "COUNTIF": ['COUNTIF(D!Q1:Q8,1)', 'COUNTIF(D!Q1:Q8,">=4")', 'COUNTIF(D!C1:C6,"b*")', 'COUNTIF(D!B1:B8,"<>1")',
                'COUNTIF(D!C1:C6,"a~*b?c")', 'COUNTIF(D!B1:B8,"")', 'COUNTIF(D!B1:B8,TRUE)',
                'COUNTIF(D!B1:B8,"#DIV/0!")'],
    "COUNTIFS": ['COUNTIFS(D!E1:E5,">1",D!G1:G5,">15")'],
    "DEVSQ": ["DEVSQ(D!Q1:Q8)"], "GEOMEAN": ["GEOMEAN(D!Q1:Q8)", "GEOMEAN(D!A1:A4)"], "HARMEAN": ["HARMEAN(D!Q1:Q8)"],
    "LARGE": ["LARGE(D!Q1:Q8,2)", "LARGE(D!Q1:Q8,9)", "LARGE(D!B1:B8,1)"], "MAX": ["MAX(D!B1:B6)"],
    "MAXA": ["MAXA(D!B1:B6)", "MAXA(D!C1:C3)"], "MAXIFS": ['_xlfn.MAXIFS(D!G1:G5,D!E1:E5,"<5")'],
    "MEDIAN": ["MEDIAN(D!Q1:Q8)", "MEDIAN(D!Q1:Q7)", "MEDIAN(D!B1:B6)", "MEDIAN(D!C1:C3)"],
    "MIN": ["MIN(D!B1:B6)"], "MINA": ["MINA(D!B1:B6)"], "MINIFS": ['_xlfn.MINIFS(D!G1:G5,D!F1:F5,">a")'],
    "MODE": ["MODE(D!Q1:Q8)", "MODE(D!E1:E5)"], "MODE.SNGL": ["MODE.SNGL(D!Q1:Q8)"],
    "PERCENTILE": ["PERCENTILE(D!Q1:Q8,0.3)", "PERCENTILE(D!Q1:Q8,1.5)"],
    "PERCENTILE.EXC": ["PERCENTILE.EXC(D!Q1:Q8,0.25)"],
    "PERCENTILE.INC": ["PERCENTILE.INC(D!Q1:Q8,0.9)"], "PERMUT": ["PERMUT(5,2)"],
    "QUARTILE": ["QUARTILE(D!Q1:Q8,1)", "QUARTILE(D!Q1:Q8,5)"], "QUARTILE.EXC": ["QUARTILE.EXC(D!Q1:Q8,3)"],
    "QUARTILE.INC": ["QUARTILE.INC(D!Q1:Q8,3)"],
    "RANK": ["RANK(4,D!Q1:Q8)", "RANK(1,D!Q1:Q8,1)", "RANK(8,D!Q1:Q8)"], "RANK.AVG": ["RANK.AVG(1,D!Q1:Q8)"],
    "RANK.EQ": ["RANK.EQ(9,D!Q1:Q8)"], "SMALL": ["SMALL(D!Q1:Q8,3)", "SMALL(D!Q1:Q8,0)"],
    "STDEV": ["STDEV(D!Q1:Q8)", "STDEV(D!B1:B6)", "STDEV(1)"], "STDEV.P": ["STDEV.P(D!Q1:Q8)"],
    "STDEV.S": ["STDEV.S(D!Q1:Q8)"], "STDEVA": ["STDEVA(D!B1:B6)"], "STDEVP": ["STDEVP(D!Q1:Q8)"],
    "STDEVPA": ["STDEVPA(D!B1:B6)"], "VAR": ["VAR(D!Q1:Q8)", "VAR(D!A1:A8)"], "VAR.P": ["VAR.P(D!Q1:Q8)"],
    "VAR.S": ["VAR.S(D!Q1:Q8)"], "VARA": ["VARA(D!B1:B6)"], "VARP": ["VARP(D!Q1:Q8)"], "VARPA": ["VARPA(D!B1:B6)"],
    # ------------------------------------------------------------ Logical
    "AND": ["AND(D!B1:B6)", "AND(TRUE,0)"], "FALSE": ["FALSE()"], "IF": ['IF(D!B3,"y","n")', "IF(D!B5,1,2)"],
    "IFERROR": ["IFERROR(D!B7,-1)"], "IFNA": ["_xlfn.IFNA(NA(),1)", "IFNA(D!B7,1)", "IFNA(2,1)"],
    "IFS": ['_xlfn.IFS(D!A1>1,"a",D!A2>1,"b")', "IFS(FALSE,1)", "IFS(D!B7,1,TRUE,2)", "IFS(D!A1=1,D!B7,TRUE,2)"],
    "NOT": ["NOT(D!B4)"], "OR": ["OR(D!B1:B6)", "OR(0,FALSE)"],
    "SWITCH": ['_xlfn.SWITCH(D!A1,1,"one",2,"two")', 'SWITCH(3,1,"one","other")', "SWITCH(3,1,2)",
               'SWITCH("B","a",1,"b",2)', "SWITCH(D!B7,1,2)"],
    "TRUE": ["TRUE()"], "XOR": ["_xlfn.XOR(TRUE,FALSE,TRUE)", "XOR(D!B1:B3)"],
    # ------------------------------------------------------------ Information
    "ERROR.TYPE": ["ERROR.TYPE(D!B7)"], "ISBLANK": ["ISBLANK(D!B4)", "ISBLANK(D!B5)"],
    "ISERR": ["ISERR(NA())"], "ISERROR": ["ISERROR(D!B7)"], "ISEVEN": ["ISEVEN(-2.5)", "ISEVEN(D!B2)"],
    "ISLOGICAL": ["ISLOGICAL(D!B3)", "ISLOGICAL(1)"], "ISNA": ["ISNA(NA())"],
    "ISNONTEXT": ["ISNONTEXT(D!B4)", "ISNONTEXT(D!B5)"], "ISNUMBER": ["ISNUMBER(D!B2)"],
    "ISODD": ["ISODD(3)", "ISODD(D!A4)"], "ISREF": ["ISREF(D!A1)", "ISREF(1)"], "ISTEXT": ["ISTEXT(D!B2)"],
    "N": ["N(D!B3)", "N(D!B5)"], "NA": ["NA()"], "TYPE": ["TYPE(D!B2)", "TYPE(D!B3)", "TYPE(D!B7)", "TYPE(1)"],
    # ------------------------------------------------------------ Lookup & Reference
    "ADDRESS": ["ADDRESS(2,3)", "ADDRESS(2,3,4)", 'ADDRESS(1,28,2,TRUE,"Sheet 2")', "ADDRESS(0,1)"],
    "CHOOSE": ['CHOOSE(2,"a","b")', "CHOOSE(3,1,2)"], "COLUMN": ["COLUMN(D!C5)"], "COLUMNS": ["COLUMNS(D!A1:C1)"],
    "HLOOKUP": ['HLOOKUP("b",D!F2:F5,1,FALSE)', "HLOOKUP(2,D!N1:P2,2)"],
    "INDEX": ["INDEX(D!E1:G5,2,3)", "INDEX(D!E1:G5,6,1)", "INDEX(D!F1:F5,3)"],
    "LOOKUP": ["LOOKUP(3.5,D!E1:E5,D!F1:F5)", "LOOKUP(0,D!E1:E5,D!F1:F5)", 'LOOKUP("c",D!F1:G5)'],
    "MATCH": ["MATCH(3,D!E1:E5,0)", "MATCH(3.5,D!E1:E5)", 'MATCH("C",D!F1:F5,0)', 'MATCH("b*",D!C1:C6,0)',
              "MATCH(9,D!E1:E5,0)", "MATCH(0,D!E1:E5,1)"],
    "ROW": ["ROW(D!C5)", "ROW(OFFSET(D!A1,3,1))", "ROW(INDEX(D!E1:G5,3,2))"],
    "ROWS": ["ROWS(D!A1:C4)", 'ROWS(INDIRECT("D!A1:A3"))'],
    "OFFSET": ["SUM(OFFSET(D!E1,1,0,3,1))", "OFFSET(D!E1,2,1)", "OFFSET(D!E1,-1,0)", "SUM(OFFSET(D!E1:E2,1,2,2,1))",
               "COLUMNS(OFFSET(D!A1,0,0,1,3))",
               "OFFSET(INDEX(D!E1:G5,2,1),1,2)"],
    "INDIRECT": ['INDIRECT("D!E4")', 'SUM(INDIRECT("D!E1:E"&3))', 'INDIRECT("D!" & "F" & 2)', 'INDIRECT("nowhere!!")',
                 "INDIRECT(B1)"],
    "TRANSPOSE": ["INDEX(TRANSPOSE(D!E1:G2),3,1)", "SUM(TRANSPOSE(D!E1:E5))"],
    "VLOOKUP": ["VLOOKUP(3,D!E1:G5,3,FALSE)", "VLOOKUP(3.7,D!E1:G5,2)", 'VLOOKUP("d",D!F1:G5,2,FALSE)',
                "VLOOKUP(9,D!E1:G5,2,FALSE)", "VLOOKUP(3,D!E1:G5,4,FALSE)", "VLOOKUP(3,D!E1:G5,0,FALSE)",
                "VLOOKUP(0.5,D!E1:G5,2,TRUE)"],
    # ------------------------------------------------------------ Text
    "CHAR": ["CHAR(65)", "CHAR(0)"], "CLEAN": ['CLEAN("a"&CHAR(9)&"b")'], "CODE": ['CODE("A")', 'CODE("")'],
    "CONCAT": ["_xlfn.CONCAT(D!C1:C3,1,TRUE)"], "CONCATENATE": ['CONCATENATE(D!C1,"-",D!A2)'],
    "EXACT": ['EXACT("a","A")', 'EXACT(D!C1,"apple")'],
    "FIND": ['FIND("an",D!C2)', 'FIND("AN",D!C2)', 'FIND("a",D!C2,3)', 'FIND("a",D!C2,30)'],
    "FIXED": ["FIXED(1234.567,1)", "FIXED(-1234.567,-2,TRUE)", "FIXED(0.5)"],
    "LEFT": ["LEFT(D!C1,3)", "LEFT(D!C1)", "LEFT(D!C1,-1)", "LEFT(12345,2)"], "LEN": ["LEN(D!C4)", "LEN(D!B3)"],
    "LOWER": ["LOWER(D!C6)"], "MID": ["MID(D!C2,2,3)", "MID(D!C2,10,3)", "MID(D!C2,0,3)"],
    "PROPER": ['PROPER("hello wORLD 2nd")'], "REPLACE": ['REPLACE(D!C1,2,3,"XY")'], "REPT": ['REPT("ab",3)'],
    "RIGHT": ["RIGHT(D!C1,2)", "RIGHT(D!C1,10)"],
    "SEARCH": ['SEARCH("AN",D!C2)', 'SEARCH("?e",D!C3)', 'SEARCH("z",D!C3)'],
    "SUBSTITUTE": ['SUBSTITUTE(D!C2,"a","o")', 'SUBSTITUTE(D!C2,"a","o",2)', 'SUBSTITUTE(D!C2,"","o")'],
    "T": ["T(D!C1)", "T(D!A1)"],
    "TEXT": ['TEXT(3.14159,"0.00")', 'TEXT(1234.5,"#,##0.0")', 'TEXT(0.256,"0%")', 'TEXT(-2,"0")',
             'TEXT(12345.678,"0.00E+00")', 'TEXT(D!C1,"0.0")', 'TEXT(0.5,"#.##")'],
    "TEXTJOIN": ['_xlfn.TEXTJOIN(", ",TRUE,D!B1:B6)', 'TEXTJOIN("-",FALSE,D!B1:B6)'],
    "TRIM": ["TRIM(D!C4)"], "UNICHAR": ["_xlfn.UNICHAR(937)"], "UNICODE": ['_xlfn.UNICODE("Ω")'],
    "UPPER": ["UPPER(D!C6)"], "VALUE": ['VALUE(" 12.5 ")', 'VALUE("x")'],
}

# formulas whose cells are array formulas over a range (Ctrl+Shift+Enter): anchor, range, formula
ARRAYS = [("D30", "D30:E31", "MMULT(D!H1:I2,D!J1:K2)"), ("D33", "D33:E34", "MINVERSE(D!H1:I2)"),
          ("D36", "D36:E38", "TRANSPOSE(D!N1:P2)")]

# Where LibreOffice 7.4 is documented to differ from Excel; sheetkin follows Excel. formula -> why
BOOLEANS = "LibreOffice's booleans are numbers: a TRUE in a range counts as 1, and as text is 1 (Excel: skipped, TRUE)"
EXCEL_DIFFERS: dict[str, str] = {
    **{f: BOOLEANS for f in (
        "SUM(D!B1:B6)", "AVERAGE(D!B1:B6)", "COUNT(D!B1:B8)", 'COUNT(1,"2",D!B3)', 'COUNTIF(D!B1:B8,"<>1")',
        "COUNTIF(D!B1:B8,TRUE)", "MEDIAN(D!B1:B6)", "STDEV(D!B1:B6)", "LEN(D!B3)", "TYPE(D!B3)",
        "_xlfn.CONCAT(D!C1:C3,1,TRUE)", '_xlfn.TEXTJOIN(", ",TRUE,D!B1:B6)', 'TEXTJOIN("-",FALSE,D!B1:B6)')},
    "ATAN2(0,0)": "Excel: #DIV/0!; LibreOffice 0",
    "POWER(0,-1)": "Excel: #DIV/0!; LibreOffice #NUM!",
    "MROUND(10,-3)": "Excel: #NUM! (number and multiple of different signs); LibreOffice 9",
    "RANK(8,D!Q1:Q8)": "Excel: #N/A (8 is not in the list); LibreOffice ranks it anyway (2)",
    **{f: "Excel: #DIV/0!; LibreOffice #NUM! (saved as #VALUE! or #NUM!)"
       for f in ("COT(0)", "COTH(0)", "CSC(0)", "CSCH(0)", "LOG(8,1)", "QUOTIENT(1,0)")},
    **{f: "Excel: #N/A; LibreOffice #VALUE!" for f in ("SUMXMY2(D!E1:E5,D!Q1:Q4)", "MODE(D!E1:E5)")},
    **{f: "Excel: #REF! (past the table); LibreOffice #VALUE!"
       for f in ("INDEX(D!E1:G5,6,1)", "VLOOKUP(3,D!E1:G5,4,FALSE)")},
    "OFFSET(D!E1,-1,0)": "Excel: #REF! (off the sheet); LibreOffice #VALUE!",
    "CHAR(0)": "Excel: #VALUE! (codes 1 to 255); LibreOffice the character 0",
    'CODE("")': "Excel: #VALUE!; LibreOffice 0",
}
# Where Gnumeric (1.12) differs from Excel's documented answer; sheetkin follows Excel
GNUMERIC_DIFFERS: dict[str, str] = {
    "ACOT(-2)": "Excel: ACOT is in (0, pi), 2.678; Gnumeric -0.464",
    'ARABIC("ab")': "Excel: #VALUE! for letters that are not Roman numerals; Gnumeric 0",
    "BASE(-1,2)": "Excel: #NUM! for a negative number; Gnumeric the two's complement",
    "CEILING(-2.5,2)": "Excel 2010 on: -2 (toward zero); Gnumeric #NUM! (Excel 2007's rule)",
    "EXP(1000)": "Excel: #NUM! past the largest number; Gnumeric writes infinity",
    "VAR(D!A1:A8)": "Excel: #NUM! past the largest number; Gnumeric writes infinity",
    "FACT(5.9)": "Excel truncates to 5! = 120; Gnumeric the gamma function",
    'COUNTIF(D!B1:B8,"#DIV/0!")': "Excel counts cells holding that error; Gnumeric 0",
    "IF(D!B5,1,2)": "Excel: a text condition is #VALUE!; Gnumeric takes it as FALSE",
    "IFS(FALSE,1)": "Excel: #N/A when no condition holds; Gnumeric #VALUE!",
    'SWITCH("B","a",1,"b",2)': "Excel compares text case-insensitively (as =); Gnumeric exactly",
    "ISEVEN(D!B2)": "Excel: #VALUE! for text; Gnumeric converts the text 2",
}
# LibreOffice's Err:502 (an argument outside the function's domain), which Excel calls #NUM!,
# is saved to .xlsx as #VALUE!: where sheetkin gives Excel's #NUM!, LibreOffice's #VALUE! agrees
NUM_AS_VALUE = "#NUM!"

# functions newer than Excel 2007, which Excel stores as _xlfn.NAME (LibreOffice reads only that form)
NEWER = {"ACOT", "ACOTH", "ARABIC", "BASE", "CEILING.MATH", "CEILING.PRECISE", "COMBINA", "COT", "COTH", "CSC", "CSCH",
         "DECIMAL", "FLOOR.MATH", "FLOOR.PRECISE", "MUNIT", "SEC", "SECH", "IFNA", "IFS", "SWITCH", "XOR", "MAXIFS",
         "MINIFS", "CONCAT", "TEXTJOIN", "UNICHAR", "UNICODE", "STDEV.P", "STDEV.S", "VAR.P", "VAR.S", "MODE.SNGL",
         "PERCENTILE.EXC", "PERCENTILE.INC", "QUARTILE.EXC", "QUARTILE.INC", "RANK.AVG", "RANK.EQ"}
_CALL = re.compile(r"(?<![\w.])([A-Z][A-Z0-9.]*)\(")


def stored(formula: str) -> str:
    """The formula as Excel stores it: the newer functions with their _xlfn. prefix."""
    return _CALL.sub(lambda m: ("_xlfn." if m[1] in NEWER else "") + m[0], formula)


SYNTAX = {"ANCHORARRAY", "SINGLE", ":"}   # Excel 365 syntax, tested in test_real_files.py; the range
                                           # operator of A1:INDEX(...), in test_range_ends.py


def write_book(path: Path) -> dict[str, str]:
    """The book at `path`; returns {cell of sheet F: formula} for every formula written."""
    wb = openpyxl.Workbook()
    ws = wb.active
    ws.title = "F"
    d = wb.create_sheet("D")
    for a, v in DATA.items():
        d[a] = v
    wb.create_sheet("Sheet 2")
    out = {}
    row = 1
    for name, formulas in CASES.items():
        for f in formulas:
            ws.cell(row=row, column=1, value=name)
            ws.cell(row=row, column=2, value="=" + stored(f))
            out[f"B{row}"] = f
            row += 1
    for anchor, ref, f in ARRAYS:
        ws[anchor] = ArrayFormula(ref, "=" + stored(f))
        out[anchor] = f
    wb.save(path)
    return out
