"""bodyplay.cloth"""
