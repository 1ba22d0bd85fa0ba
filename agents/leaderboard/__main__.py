from agents.leaderboard.board import main

main()
